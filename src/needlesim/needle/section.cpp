#include "needlesim/needle/section.hpp"

#include <stdexcept>

namespace needlesim::needle {

DimensionalGroups dimensionalGroups(const DimensionalInput& in) {
  if (!(in.E > 0 && in.I > 0 && in.C10 > 0 && in.Gc > 0))
    throw std::invalid_argument("dimensional analysis needs E, I, C10 and Gc > 0");
  DimensionalGroups g;
  const double I4 = std::sqrt(std::sqrt(in.I)), I2 = std::sqrt(in.I);
  const double EC = in.E * in.C10, G2 = in.Gc * in.Gc;
  g.rho0 = G2 / (EC * I4);                   // seed 002 eq 3
  g.Pi1 = in.rho / g.rho0;                   // seed 002 eq 2
  g.Pi2 = in.P_input * EC * I4 / (G2 * in.Gc);
  g.Pi3 = in.alpha * EC * I2 / G2;
  g.Pi4 = in.mu * EC * I2 / G2;
  const double C2 = in.C10 * in.C10;
  g.s004_length = in.E * in.Gc / C2;         // seed 004 eq 3
  g.s004_Pi1 = in.rho / g.s004_length;
  g.s004_Pi2 = in.I * C2 * C2 * in.C10 / (in.E * G2 * G2);
  g.s004_Pi3 = in.u / g.s004_length;
  return g;
}

}  // namespace needlesim::needle
