#pragma once
// Penalty laws of normal contact (docs/models/contact.md): the force that
// pushes a penetrating point out, as a function of its penetration, with the
// derivative (the contact's tangent stiffness) and the stored energy.
// Header-only and inline: these sit in the solvers' contact loops.
#include <cmath>

namespace needlesim::contact {

// Linear penalty: f = k g for a penetration g > 0, 0 when separated (g <= 0);
// df/dg = k (0 when separated); stored energy U = k g^2 / 2 (dU/dg = f).
constexpr double penaltyForce(double k, double depth) noexcept { return depth > 0.0 ? k * depth : 0.0; }
constexpr double penaltySlope(double k, double depth) noexcept { return depth > 0.0 ? k : 0.0; }
constexpr double penaltyEnergy(double k, double depth) noexcept { return depth > 0.0 ? 0.5 * k * depth * depth : 0.0; }

// The explicit FE's stiffness (docs/models/explicit.md "Contact stiffness"):
// a multiple `factor` of the node's mass m over the step squared,
// k = factor m / dt^2 (factor 1: the stiffness of the node's own elements,
// m / dt_stable^2, up to a constant).
constexpr double massPenalty(double factor, double m, double dt) noexcept { return factor / (dt * dt) * m; }

// The MPM pair law of two material points whose volumes overlap by delta at
// contact distance d (mpm/penalty_contact.hpp; a departure from seed 000,
// whose normal contact is the impulse of eqs 15-18): linear up to the onset
// delta_s = a d, beyond it the barrier f = k delta (G / r)^m, G = d - delta_s,
// r = d - delta (a = 0.3, m = 6: f(d/2) = 3.8 k d). Force, tangent
// df/ddelta and potential U = int_0^delta f, for 0 < delta < d.
inline constexpr double kPairOnset = 0.3;  // a: the barrier starts at 0.3 d (the block impact stays below it)
inline constexpr double kPairPower = 6.0;  // m: f(d/2) = 3.8 k d, a face pressure 3.8 kappa M held at half a spacing

inline double pairPenaltyForce(double k, double delta, double d) {
  const double s = kPairOnset * d;
  if (delta <= s) return k * delta;
  const double G = d - s, r = d - delta;
  return k * delta * std::pow(G / r, kPairPower);
}

inline double pairPenaltyTangent(double k, double delta, double d) {
  const double s = kPairOnset * d;
  if (delta <= s) return k;
  const double G = d - s, r = d - delta, m = kPairPower;
  return k * std::pow(G / r, m) * (1.0 + m * delta / r);
}

// U = 1/2 k delta_s^2 + k G^m int_{delta_s}^{delta} y (d - y)^-m dy
//   = 1/2 k delta_s^2 + k [d G (rho^(m-1) - 1) / (m-1) - G^2 (rho^(m-2) - 1) / (m-2)],
// rho = G / r (m > 2; expm1/log1p keep the small-overlap differences exact).
inline double pairPenaltyEnergy(double k, double delta, double d) {
  const double s = kPairOnset * d;
  if (delta <= s) return 0.5 * k * delta * delta;
  const double G = d - s, r = d - delta, m = kPairPower;
  const double l = std::log1p((delta - s) / r);  // log rho
  return k * (0.5 * s * s + d * G * std::expm1((m - 1) * l) / (m - 1) - G * G * std::expm1((m - 2) * l) / (m - 2));
}

}  // namespace needlesim::contact
