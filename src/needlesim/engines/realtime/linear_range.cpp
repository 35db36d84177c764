// Strains, rotations and volume ratios of the real-time engines' tissue (linear_range.hpp).
#include "needlesim/engines/realtime/linear_range.hpp"

#include <fmt/format.h>

#include <Eigen/Dense>
#include <cmath>

namespace needlesim::realtime {

SimplexStrains::SimplexStrains(int dim, std::vector<double> X, std::vector<int> simplices)
    : dim_(dim), X_(std::move(X)), simplices_(std::move(simplices)) {}

// In 2D R = [c -s; s c] with tan(theta) = (F10 - F01) / (F00 + F11) (F = R U, U symmetric).
double rotationAngle(const Eigen::Matrix2d& F) { return std::abs(std::atan2(F(1, 0) - F(0, 1), F(0, 0) + F(1, 1))); }

// R = F U^-1 with U^-1 = V diag(1 / sqrt(lambda)) V^T from the eigenpairs of C = F^T F (the closed-form
// solver the strain uses; no SVD); the angle from sin and cos: |axial(R)| and (tr R - 1) / 2.
double rotationAngle(const Eigen::Matrix3d& F) {
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es;
  es.computeDirect(F.transpose() * F);
  const Eigen::Vector3d inv = es.eigenvalues().cwiseMax(1e-300).cwiseSqrt().cwiseInverse();
  const Eigen::Matrix3d R = F * es.eigenvectors() * inv.asDiagonal() * es.eigenvectors().transpose();
  const Eigen::Vector3d axial(R(2, 1) - R(1, 2), R(0, 2) - R(2, 0), R(1, 0) - R(0, 1));
  return std::atan2(0.5 * axial.norm(), 0.5 * (R.trace() - 1.0));
}

namespace {
// grad u = dU dX^-1 of one simplex (edges from its first corner), its J, largest |strain| and rotation.
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
  else d.max_rotation = std::max(d.max_rotation, rotationAngle(Eigen::Matrix<double, D, D>(Eigen::Matrix<double, D, D>::Identity() + G)));
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
  worstRotation_ = std::max(worstRotation_, d.max_rotation);
  const bool strained = d.max_strain > kLinearStrainBound, rotated = d.max_rotation > kLinearRotationBound;
  if (warned_ || (d.inverted == 0 && !strained && !rotated)) return warned_;
  warned_ = true;
  const std::string inverted =
      d.inverted > 0 ? fmt::format("{} element{} inverted (det J <= 0); ", d.inverted, d.inverted == 1 ? " is" : "s are") : "";
  sink.warning(fmt::format(
      "{}: the linear tissue model no longer holds at tip depth {:.3g} mm: {}the largest strain is {:.3g}{} and the "
      "largest element rotation {:.3g} rad{}; the small-strain model is held to a strain of {:g} and a rotation of "
      "{:g} rad, and its forces and displacements there are outside the model (a stiffer or thicker tissue, a "
      "slower insertion or a smaller lateral motion, or the explicit engine's finite strains; "
      "docs/models/realtime3d.md \"When linear elasticity holds\").",
      engine_, depth * 1e3, inverted, d.max_strain, strained ? " (beyond the bound)" : "", d.max_rotation,
      rotated ? " (beyond the bound)" : "", kLinearStrainBound, kLinearRotationBound));
  return true;
}

void reportLinearRange(const LinearRangeWarning& range, const std::string& where, ResultSink& sink) {
  sink.result("max_tissue_strain", range.worstStrain(), "1",
              "largest |principal small strain| of the tissue's elements" + where + " (linear range check)");
  sink.result("max_tissue_rotation", range.worstRotation(), "rad",
              "largest rotation of the tissue's elements" + where + " (polar decomposition of I + grad u)");
  sink.note(fmt::format("Largest small strain in the tissue{}: {:.2g}, largest element rotation {:.2g} rad (the linear "
                        "model is held to {:g} and {:g} rad; realtime/linear_range.hpp).",
                        where, range.worstStrain(), range.worstRotation(), kLinearStrainBound, kLinearRotationBound));
}

}  // namespace needlesim::realtime
