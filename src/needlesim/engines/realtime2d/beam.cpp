#include "needlesim/engines/realtime2d/beam.hpp"

#include <Eigen/Cholesky>

#include "needlesim/core/error.hpp"

namespace needlesim::realtime2d {

Eigen::Matrix4d beamElementStiffness(double EI, double L) {
  const double L2 = L * L, L3 = L2 * L;
  Eigen::Matrix4d k;
  k << 12 / L3, 6 / L2, -12 / L3, 6 / L2,  //
      6 / L2, 4 / L, -6 / L2, 2 / L,       //
      -12 / L3, -6 / L2, 12 / L3, -6 / L2, //
      6 / L2, 2 / L, -6 / L2, 4 / L;
  return EI * k;  // eq 3.14
}

CantileverFE::CantileverFE(std::vector<double> nodes, double EI) : x_(std::move(nodes)), EI_(EI) {
  if (x_.size() < 2 || !(EI > 0.0)) throw SolverError("realtime2d beam: need >= 2 nodes and EI > 0");
  const int n = static_cast<int>(x_.size());
  Eigen::MatrixXd K = Eigen::MatrixXd::Zero(2 * n, 2 * n);
  for (int e = 0; e + 1 < n; ++e) {
    const double L = x_[static_cast<std::size_t>(e + 1)] - x_[static_cast<std::size_t>(e)];
    if (!(L > 0.0)) throw SolverError("realtime2d beam: node positions must increase");
    K.block<4, 4>(2 * e, 2 * e) += beamElementStiffness(EI, L);
  }
  K_ = K.bottomRightCorner(2 * n - 2, 2 * n - 2);  // clamp: w0 = theta0 = 0
}

void CantileverFE::solve(const Eigen::VectorXd& F, const Eigen::VectorXd& Mo, Eigen::VectorXd& w,
                         Eigen::VectorXd& theta) const {
  const int n = static_cast<int>(x_.size());
  Eigen::VectorXd f(2 * n - 2);
  for (int i = 1; i < n; ++i) {
    f[2 * i - 2] = F[i];
    f[2 * i - 1] = Mo[i];
  }
  const Eigen::VectorXd d = K_.ldlt().solve(f);
  w.setZero(n);
  theta.setZero(n);
  for (int i = 1; i < n; ++i) {
    w[i] = d[2 * i - 2];
    theta[i] = d[2 * i - 1];
  }
}

}  // namespace needlesim::realtime2d
