#include "needlesim/engines/steering/curvature_fit.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/Dense>

namespace needlesim::steering {

using Vec3 = Eigen::Vector3d;

CircleFit fitCircle(std::span<const Vec3> pts, double straight_tol) {
  CircleFit f;
  const int n = static_cast<int>(pts.size());
  f.points = n;
  if (n < 3) return f;
  Vec3 c = Vec3::Zero();
  for (const Vec3& p : pts) c += p;
  c /= n;
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (const Vec3& p : pts) cov += (p - c) * (p - c).transpose();
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(cov);
  // ascending eigenvalues: col 0 = plane normal, col 2 = main direction
  const Vec3 nrm = es.eigenvectors().col(0), e1 = es.eigenvectors().col(2),
             e2 = es.eigenvectors().col(1);
  f.normal = nrm;
  const double span1 = std::sqrt(es.eigenvalues()(2) / n), span2 = std::sqrt(es.eigenvalues()(1) / n);
  if (!(span1 > 0) || span2 <= straight_tol * span1) return f;  // collinear
  // Kasa: x^2 + y^2 + D x + E y + F = 0 in least squares, coordinates scaled by span1.
  const double sc = 1.0 / span1;
  Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
  Vec3 b = Vec3::Zero();
  for (const Vec3& p : pts) {
    const double x = (p - c).dot(e1) * sc, y = (p - c).dot(e2) * sc;
    const Vec3 row(x, y, 1.0);
    A += row * row.transpose();
    b -= row * (x * x + y * y);
  }
  const Vec3 sol = A.ldlt().solve(b);
  double cx = -sol(0) / 2, cy = -sol(1) / 2;
  double r = std::sqrt(std::max(0.0, cx * cx + cy * cy - sol(2)));
  if (!std::isfinite(r) || r > 1e8) return f;
  // Gauss-Newton on the geometric distance.
  for (int it = 0; it < 20; ++it) {
    Eigen::Matrix3d JtJ = Eigen::Matrix3d::Zero();
    Vec3 Jtr = Vec3::Zero();
    for (const Vec3& p : pts) {
      const double x = (p - c).dot(e1) * sc, y = (p - c).dot(e2) * sc;
      const double dx = x - cx, dy = y - cy, di = std::hypot(dx, dy);
      if (di == 0) continue;
      const Vec3 J(-dx / di, -dy / di, -1.0);
      const double res = di - r;
      JtJ += J * J.transpose();
      Jtr += J * res;
    }
    const Vec3 step = JtJ.ldlt().solve(-Jtr);
    cx += step(0);
    cy += step(1);
    r += step(2);
    if (step.norm() < 1e-13 * (1 + r)) break;
  }
  double ss = 0;
  for (const Vec3& p : pts) {
    const double x = (p - c).dot(e1) * sc, y = (p - c).dot(e2) * sc;
    const double res = std::hypot(x - cx, y - cy) - r;
    ss += res * res;
  }
  f.radius = r / sc;
  f.rms = std::sqrt(ss / n) / sc;
  f.centre = c + (cx * e1 + cy * e2) / sc;
  return f;
}

std::span<const Vec3> pathSection(std::span<const Vec3> pts, double s0, double s1) {
  const int n = static_cast<int>(pts.size());
  double s = 0;
  int first = -1, last = -1;
  for (int i = 0; i < n; ++i) {
    if (i > 0) s += (pts[i] - pts[i - 1]).norm();
    if (s >= s0 - 1e-12 && first < 0) first = i;
    if (s <= s1 + 1e-12) last = i;
  }
  if (first < 0 || last < first) return {};
  return pts.subspan(first, last - first + 1);
}

CircleFit fitCircleSection(std::span<const Vec3> pts, double s0, double s1) {
  const auto section = pathSection(pts, s0, s1);
  return section.empty() ? CircleFit{} : fitCircle(section);
}

double sagitta(std::span<const Vec3> pts) {
  if (pts.size() < 3) return 0.0;
  const Vec3 a = pts.front(), chord = pts.back() - a;
  const double len = chord.norm();
  double most = 0.0;
  for (const Vec3& p : pts) {
    const Vec3 d = p - a;
    most = std::max(most, len > 0 ? (d - d.dot(chord / len) * chord / len).norm() : d.norm());
  }
  return most;
}

bool isOneArc(const CircleFit& fit, std::span<const Vec3> pts) {
  return std::isfinite(fit.radius) && fit.rms <= kOneArcRmsShare * sagitta(pts);
}

std::vector<PathPiece> pathPieces(std::span<const Vec3> pts, std::span<const double> breaks) {
  double total = 0.0;
  for (std::size_t i = 1; i < pts.size(); ++i) total += (pts[i] - pts[i - 1]).norm();
  std::vector<double> ends{0.0};
  for (double b : breaks)
    if (b > ends.back() + 1e-9 && b < total - 1e-9) ends.push_back(b);
  ends.push_back(total);
  std::vector<PathPiece> pieces;
  for (std::size_t k = 0; k + 1 < ends.size(); ++k) {
    PathPiece p{ends[k], ends[k + 1], {}, false, false};
    const auto section = pathSection(pts, p.s0, p.s1);
    p.fit = fitCircle(section);
    p.straight = !std::isfinite(p.fit.radius);
    p.arc = isOneArc(p.fit, section);
    pieces.push_back(p);
  }
  return pieces;
}

SectionRadii sectionRadii(std::span<const Vec3> pts, double section) {
  SectionRadii r;
  for (int k = 0; k < 3; ++k) r.rho[k] = fitCircleSection(pts, k * section, (k + 1) * section).radius;
  r.mean = (r.rho[0] + r.rho[1] + r.rho[2]) / 3.0;
  r.whole = fitCircle(pts).radius;
  return r;
}

}  // namespace needlesim::steering
