// Strains, rotations and volume ratios of the real-time engines' tissue (linear_range.hpp).
#include "needlesim/engines/realtime/linear_range.hpp"

#include <fmt/format.h>

#include <Eigen/Dense>
#include <cmath>
#include <numbers>

namespace needlesim::realtime {

namespace {
// dX^-1 of each simplex: its edges from the first corner, column-major, D x D each.
template <int D>
std::vector<double> inverseEdgesOf(const std::vector<double>& X, const std::vector<int>& simplices) {
  std::vector<double> out;
  for (std::size_t e = 0; e + D + 1 <= simplices.size(); e += D + 1) {
    Eigen::Matrix<double, D, D> dX;
    const int* s = &simplices[e];
    for (int c = 0; c < D; ++c)
      for (int k = 0; k < D; ++k) dX(k, c) = X[D * s[c + 1] + k] - X[D * s[0] + k];
    const Eigen::Matrix<double, D, D> inv = dX.inverse();
    out.insert(out.end(), inv.data(), inv.data() + D * D);
  }
  return out;
}
}  // namespace

SimplexStrains::SimplexStrains(int dim, const std::vector<double>& X, std::vector<int> simplices)
    : dim_(dim), simplices_(std::move(simplices)),
      inverseEdges_(dim == 2 ? inverseEdgesOf<2>(X, simplices_) : inverseEdgesOf<3>(X, simplices_)) {}

// In 2D R = [c -s; s c] with tan(theta) = (F10 - F01) / (F00 + F11) (F = R U, U symmetric).
double rotationAngle(const Eigen::Matrix2d& F) { return std::abs(std::atan2(F(1, 0) - F(0, 1), F(0, 0) + F(1, 1))); }

// R by Newton's iteration R <- (R + R^-T) / 2 from R = F (Higham 1986, "Computing the polar
// decomposition"): quadratic, three or four 3 x 3 inverses for the strains of interest, scaled by
// g = |det R|^(-1/3) while far from converged; the angle from sin and cos: |axial(R)| and (tr R - 1) / 2.
double rotationAngle(const Eigen::Matrix3d& F) {
  Eigen::Matrix3d R = F;
  double change = 1.0;
  for (int k = 0; k < 30 && change > 1e-5; ++k) {  // the error after a step is about change^2
    const double g = change > 0.1 ? std::cbrt(1.0 / std::abs(R.determinant())) : 1.0;
    const Eigen::Matrix3d next = 0.5 * (g * R + R.inverse().transpose() / g);
    change = (next - R).cwiseAbs().maxCoeff();
    R = next;
  }
  const Eigen::Vector3d axial(R(2, 1) - R(1, 2), R(0, 2) - R(2, 0), R(1, 0) - R(0, 1));
  return std::atan2(0.5 * axial.norm(), 0.5 * (R.trace() - 1.0));
}

namespace {
// Bounds on the rotation theta of the polar decomposition of F = I + E + W (E, W the symmetric and skew parts
// of G), so that the decomposition is needed only where the upper one passes the largest rotation known. Q = exp(W)
// turns by w = |axial(W)|; R is the rotation nearest F (Frobenius norm), so |R - Q| <= |R - F| + |F - Q|
// <= 2 |F - Q|, |F - Q| <= |E| + sqrt(2) (w - sin w + 1 - cos w), and the angle phi between R and Q has
// |R - Q| = 2 sqrt(2) sin(phi / 2): w - phi <= theta <= w + phi.
template <int D>
std::pair<double, double> rotationBounds(const Eigen::Matrix<double, D, D>& G) {
  const Eigen::Matrix<double, D, D> E = 0.5 * (G + G.transpose());
  const Eigen::Matrix<double, D, D> W = 0.5 * (G - G.transpose());
  const double w = W.norm() / std::sqrt(2.0);
  const double off = E.norm() + std::sqrt(2.0) * (w - std::sin(w) + 1.0 - std::cos(w));
  const double phi = 2.0 * std::asin(std::min(1.0, off / std::sqrt(2.0)));
  return {w <= std::numbers::pi ? std::max(0.0, w - phi) : 0.0, w + phi};  // exp(W) turns by w up to pi
}

// grad u = dU dX^-1 of one simplex (edges from its first corner, dX^-1 given) in G, its J and largest
// |strain| into d, d.max_rotation raised to the rotation's lower bound; returns the upper one (-1: inverted).
template <int D>
double addSimplex(const double* inverseEdges, const Eigen::VectorXd& u, const int* s, Deformation& d,
                  Eigen::Matrix<double, D, D>& G) {
  Eigen::Matrix<double, D, D> dU;
  for (int e = 0; e < D; ++e)
    for (int k = 0; k < D; ++k) dU(k, e) = u[D * s[e + 1] + k] - u[D * s[0] + k];
  G = dU * Eigen::Map<const Eigen::Matrix<double, D, D>>(inverseEdges);
  const Eigen::Matrix<double, D, D> eps = 0.5 * (G + G.transpose());
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, D, D>> es;
  es.computeDirect(eps, Eigen::EigenvaluesOnly);
  d.max_strain = std::max(d.max_strain, es.eigenvalues().cwiseAbs().maxCoeff());
  if (!((Eigen::Matrix<double, D, D>::Identity() + G).determinant() > 0.0)) {
    ++d.inverted;
    return -1.0;
  }
  // One Newton step of the polar decomposition (F_1 = (F + F^-T) / 2, same R, strain part of order |G|^2)
  // tightens the bounds.
  const Eigen::Matrix<double, D, D> F = Eigen::Matrix<double, D, D>::Identity() + G;
  const auto [lower, upper] = rotationBounds<D>(Eigen::Matrix<double, D, D>(0.5 * (F + F.inverse().transpose()) - Eigen::Matrix<double, D, D>::Identity()));
  d.max_rotation = std::max(d.max_rotation, lower);
  return upper;
}

// Every simplex's strain and J, then the exact rotation of those whose upper bound passes the largest
// lower bound (the largest exact one as it grows).
template <int D>
void measureAll(const std::vector<double>& inverseEdges, const std::vector<int>& simplices, const Eigen::VectorXd& u,
                Deformation& d) {
  using Mat = Eigen::Matrix<double, D, D>;
  const std::size_t count = simplices.size() / (D + 1);
  std::vector<Mat> G(count);
  std::vector<double> upper(count);
  for (std::size_t e = 0; e < count; ++e)
    upper[e] = addSimplex<D>(&inverseEdges[D * D * e], u, &simplices[(D + 1) * e], d, G[e]);
  for (std::size_t e = 0; e < count; ++e)
    if (upper[e] > d.max_rotation) d.max_rotation = std::max(d.max_rotation, rotationAngle(Mat(Mat::Identity() + G[e])));
}
}  // namespace

Deformation SimplexStrains::measure(const Eigen::VectorXd& u) const {
  Deformation d;
  if (dim_ == 2) measureAll<2>(inverseEdges_, simplices_, u, d);
  else measureAll<3>(inverseEdges_, simplices_, u, d);
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
