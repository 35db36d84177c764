// Strains and volume ratios of the real-time engines' tissue (linear_range.hpp).
#include "needlesim/engines/realtime/linear_range.hpp"

#include <fmt/format.h>

#include <Eigen/Dense>
#include <cmath>

namespace needlesim::realtime {

SimplexStrains::SimplexStrains(int dim, std::vector<double> X, std::vector<int> simplices)
    : dim_(dim), X_(std::move(X)), simplices_(std::move(simplices)) {}

namespace {
// grad u = dU dX^-1 of one simplex (edges from its first corner), its J and largest |strain|.
template <int D>
void addSimplex(const double* X, const Eigen::VectorXd& u, const int* s, Deformation& d) {
  Eigen::Matrix<double, D, D> dX, dU;
  for (int e = 0; e < D; ++e)
    for (int k = 0; k < D; ++k) {
      dX(k, e) = X[D * s[e + 1] + k] - X[D * s[0] + k];
      dU(k, e) = u[D * s[e + 1] + k] - u[D * s[0] + k];
    }
  const Eigen::Matrix<double, D, D> G = dU * dX.inverse();
  const double J = (Eigen::Matrix<double, D, D>::Identity() + G).determinant();
  if (!(J > 0.0)) ++d.inverted;
  const Eigen::Matrix<double, D, D> eps = 0.5 * (G + G.transpose());
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, D, D>> es;
  es.computeDirect(eps, Eigen::EigenvaluesOnly);
  d.max_strain = std::max(d.max_strain, es.eigenvalues().cwiseAbs().maxCoeff());
}
}  // namespace

Deformation SimplexStrains::measure(const Eigen::VectorXd& u) const {
  Deformation d;
  const int n = dim_ + 1;
  for (std::size_t e = 0; e + static_cast<std::size_t>(n) <= simplices_.size(); e += static_cast<std::size_t>(n)) {
    if (dim_ == 2) addSimplex<2>(X_.data(), u, &simplices_[e], d);
    else addSimplex<3>(X_.data(), u, &simplices_[e], d);
  }
  return d;
}

std::vector<int> quadCornerTriangles(const std::vector<std::array<int, 4>>& quads) {
  std::vector<int> t;
  for (const auto& q : quads) {
    if (q[2] == q[3]) {  // a collapsed quad: the triangle a, b, c
      t.insert(t.end(), {q[0], q[1], q[2]});
      continue;
    }
    for (int c = 0; c < 4; ++c) t.insert(t.end(), {q[c], q[(c + 1) % 4], q[(c + 3) % 4]});
  }
  return t;
}

bool LinearRangeWarning::check(const Deformation& d, double depth, ResultSink& sink) {
  worst_ = std::max(worst_, d.max_strain);
  if (warned_ || (d.inverted == 0 && !(d.max_strain > kLinearStrainBound))) return warned_;
  warned_ = true;
  const std::string inverted =
      d.inverted > 0 ? fmt::format("{} element{} inverted (det J <= 0) and ", d.inverted, d.inverted == 1 ? " is" : "s are") : "";
  sink.warning(fmt::format(
      "{}: the linear tissue model no longer holds at tip depth {:.3g} mm: {}the largest strain is {:.2g}, beyond "
      "the {:g} the small-strain model is held to; its forces and displacements there are outside the model "
      "(a stiffer or thicker tissue, a slower insertion, or the explicit engine's finite strains).",
      engine_, depth * 1e3, inverted, d.max_strain, kLinearStrainBound));
  return true;
}

}  // namespace needlesim::realtime
