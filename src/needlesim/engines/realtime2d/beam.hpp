#pragma once
// Euler-Bernoulli needle for the real-time 2D engine (seed 003 eqs 3.12-3.15):
// cubic Hermite beam elements with deflection and rotation per node (eq 3.14,
// with the symmetric element matrix: the extraction's 4/L in row 4 col 2 is 2/L),
// clamped at the base guide. The coupled solve uses the beam's exact static
// condensation onto its loaded points: for a cantilever clamped at sigma = 0 the
// Hermite FE with nodes at the load points reproduces the closed-form influence
// function w(a) per unit load at b = min^2 (3 max - min) / (6 EI) (the k_i l^3/3EI
// terms of eq 3.12), which tests/realtime2d checks against the assembled FE.
// TODO(merge): fold into src/needlesim/needle's beam element once both settle.
#include <Eigen/Core>
#include <vector>

namespace needlesim::realtime2d {

// Element stiffness (eq 3.14) for DOFs (w1, theta1, w2, theta2).
Eigen::Matrix4d beamElementStiffness(double EI, double L);

// A clamped cantilever of nodes at positions 0 = x_0 < x_1 < ... (m), solved by FE.
class CantileverFE {
 public:
  CantileverFE(std::vector<double> nodes, double EI);
  // Static deflections and rotations at the nodes for nodal forces F and moments Mo.
  void solve(const Eigen::VectorXd& F, const Eigen::VectorXd& Mo, Eigen::VectorXd& w, Eigen::VectorXd& theta) const;
  const Eigen::MatrixXd& stiffness() const { return K_; }  // free DOFs (node 1..)

 private:
  std::vector<double> x_;
  double EI_;
  Eigen::MatrixXd K_;
};

// Closed-form cantilever influence functions (clamped at sigma = 0).
inline double cantileverDeflection(double a, double b, double EI) {  // at a, unit force at b
  const double lo = a < b ? a : b, hi = a < b ? b : a;
  return lo * lo * (3.0 * hi - lo) / (6.0 * EI);
}
inline double cantileverSlope(double a, double b, double EI) {  // slope at a, unit force at b
  return a <= b ? a * (2.0 * b - a) / (2.0 * EI) : b * b / (2.0 * EI);
}

}  // namespace needlesim::realtime2d
