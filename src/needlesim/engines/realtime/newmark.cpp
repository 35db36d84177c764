#include "needlesim/engines/realtime/newmark.hpp"

#include "needlesim/core/error.hpp"

namespace needlesim::realtime {

NewmarkCoefficients::NewmarkCoefficients(const NewmarkParams& p, double h) {
  if (!(h > 0.0)) throw SolverError("realtime: the time step must be > 0");
  if (!(p.beta > 0.0) || !(p.gamma > 0.0)) throw SolverError("realtime: Newmark gamma and beta must be > 0");
  dt = h;
  a0 = 1.0 / (p.beta * h * h);
  a1 = p.gamma / (p.beta * h);
  a2 = 1.0 / (p.beta * h);
  a3 = 1.0 / (2.0 * p.beta) - 1.0;
  a4 = p.gamma / p.beta - 1.0;
  a5 = 0.5 * h * (p.gamma / p.beta - 2.0);
}

}  // namespace needlesim::realtime
