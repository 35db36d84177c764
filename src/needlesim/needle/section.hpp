#pragma once
// Needle cross-section and the dimensional analysis of bevel-tip steering.
// SI units throughout: m, Pa, N, rad.
#include <cmath>
#include <numbers>

namespace needlesim::needle {

// Circular (solid or hollow) needle section of Young's modulus E.
struct Section {
  double youngs_modulus = 50e9;  // Pa (Nitinol, seed 002 section 5.2)
  double outer_diameter = 0.0;   // m
  double inner_diameter = 0.0;   // m, 0 = solid wire

  double area() const {
    const double d = outer_diameter, di = inner_diameter;
    return std::numbers::pi / 4.0 * (d * d - di * di);
  }
  // Second moment of area pi (d^4 - di^4) / 64.
  double secondMoment() const {
    const double d2 = outer_diameter * outer_diameter, di2 = inner_diameter * inner_diameter;
    return std::numbers::pi / 64.0 * (d2 * d2 - di2 * di2);
  }
  double EI() const { return youngs_modulus * secondMoment(); }
  double EA() const { return youngs_modulus * area(); }
};

// Pi groups of seed 002 eqs 1-3 (primary variables E, I, C10, Gc) and
// seed 004 eqs 2-3 (primary variables E, C10, Gc). The radius of curvature
// rho is optional (0 = unknown, the rho-groups are then 0).
struct DimensionalInput {
  double E = 0.0;        // Pa, needle Young's modulus
  double I = 0.0;        // m^4, second moment of area
  double alpha = 0.0;    // rad, bevel angle
  double C10 = 0.0;      // Pa, Neo-Hookean constant of the tissue
  double Gc = 0.0;       // J/m^2 (= N/m), rupture toughness
  double mu = 0.0;       // -, friction coefficient
  double P_input = 0.0;  // N, insertion force
  double u = 0.0;        // m, input displacement (seed 004)
  double rho = 0.0;      // m, radius of curvature if known
};

struct DimensionalGroups {
  // seed 002 eq 2-3
  double rho0 = 0.0;  // m, length scale Gc^2 / (E C10 I^(1/4))  (eq 3)
  double Pi1 = 0.0;   // rho / rho0
  double Pi2 = 0.0;   // P_input E C10 I^(1/4) / Gc^3
  double Pi3 = 0.0;   // alpha E C10 sqrt(I) / Gc^2
  double Pi4 = 0.0;   // mu E C10 sqrt(I) / Gc^2
  // seed 004 eq 2-3
  double s004_Pi1 = 0.0;  // rho C10^2 / (E Gc)
  double s004_Pi2 = 0.0;  // I C10^5 / (E Gc^4)
  double s004_Pi3 = 0.0;  // u C10^2 / (E Gc)
  double s004_length = 0.0;  // m, E Gc / C10^2: the seed 004 length scale
};

// Throws std::invalid_argument if E, I, C10 or Gc is not positive.
DimensionalGroups dimensionalGroups(const DimensionalInput& in);

}  // namespace needlesim::needle
