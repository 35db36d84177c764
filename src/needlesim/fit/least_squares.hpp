#pragma once
// Nonlinear least squares with bounds by reparametrisation, on Eigen's
// Levenberg-Marquardt (unsupported/Eigen/NonLinearOptimization, MINPACK lmder).
// The solver works on unconstrained internal parameters p; the physical
// parameters theta = physical(p) (e.g. theta = exp(p) for a positive modulus)
// keep their bounds by construction. Standard errors come from the Jacobian at
// the optimum: Cov(theta) = s^2 D (J^T J)^-1 D^T, s^2 = SSE / (n - k),
// D = d theta / d p (delta method).
#include <Eigen/Core>
#include <functional>
#include <string>
#include <vector>

namespace needlesim::fit {

struct LsqProblem {
  int nParams = 0;
  int nResiduals = 0;
  // Residuals r(p) (model - data, preferably scaled to order 1). Must stay finite.
  std::function<void(const Eigen::VectorXd& p, Eigen::VectorXd& r)> residuals;
  std::function<Eigen::VectorXd(const Eigen::VectorXd& p)> physical;
  std::vector<Eigen::VectorXd> starts;  // multi-start: the lowest cost wins
};

struct LsqResult {
  Eigen::VectorXd p;
  Eigen::VectorXd theta;
  Eigen::VectorXd stdErr;  // NaN where the Jacobian is rank deficient
  Eigen::VectorXd residuals;
  double cost = 0.0;  // sum r^2
  bool converged = false;
  int evaluations = 0;
  std::string message;
};

LsqResult solveLeastSquares(const LsqProblem& problem);

// Small-sample corrected Akaike information criterion of a least-squares fit.
double aicc(double sse, int n, int k);

}  // namespace needlesim::fit
