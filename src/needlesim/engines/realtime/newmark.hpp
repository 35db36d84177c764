#pragma once
// Newmark time integration shared by the real-time engines (realtime2d, realtime3d):
// seed 003 eqs 3.2-3.4, the effective-stiffness form A u = Q + M(...) + C(...).
namespace needlesim::realtime {

struct NewmarkParams {
  double gamma = 0.5;   // delta of eq 3.2
  double beta = 0.25;   // xi of eq 3.3 (average acceleration: unconditionally stable)
  bool unconditionallyStable() const { return gamma >= 0.5 && beta >= 0.25 * (gamma + 0.5) * (gamma + 0.5); }
};

struct NewmarkCoefficients {  // eq 3.4 written as A u = Q + M(...) + C(...)
  double dt = 0, a0 = 0, a1 = 0, a2 = 0, a3 = 0, a4 = 0, a5 = 0;
  NewmarkCoefficients() = default;
  NewmarkCoefficients(const NewmarkParams& p, double dt);
  double gamma() const { return a2 == 0.0 ? 0.5 : a1 / a2; }
  // New acceleration (eq 3.3) of one DOF that moves from u to un in the step.
  double acceleration(double un, double u, double v, double a) const { return a0 * (un - u) - a2 * v - a3 * a; }
  // New velocity (eq 3.2) from the old acceleration a and the new one an.
  double velocity(double v, double a, double an) const { return v + dt * ((1.0 - gamma()) * a + gamma() * an); }
};

enum class Backend { Auto, Direct, Modal, Reduced };

}  // namespace needlesim::realtime
