#pragma once
// Pre-puncture stiffness force on the tip (seed 003 eq 3.16):
//   F1 = 2 E z^2 / (pi (1 - nu^2) cot(alpha) sin(theta))
// z: indentation of the surface, alpha: bevel angle, theta: insertion angle.
#include <cmath>
#include <numbers>

namespace needlesim::forces {

struct StiffnessLaw {
  double E = 0.0;      // Pa
  double nu = 0.0;     // 1
  double alpha = 0.0;  // rad, bevel angle
  double theta = std::numbers::pi / 2;  // rad, insertion angle

  double coefficient() const {  // F1 = coefficient() z^2
    return 2.0 * E * std::tan(alpha) / (std::numbers::pi * (1.0 - nu * nu) * std::sin(theta));
  }
  double force(double z) const { return z > 0.0 ? coefficient() * z * z : 0.0; }
  // Indentation at which the force reaches F (inverse of eq 3.16).
  double depthAt(double F) const { return F > 0.0 ? std::sqrt(F / coefficient()) : 0.0; }
};

}  // namespace needlesim::forces
