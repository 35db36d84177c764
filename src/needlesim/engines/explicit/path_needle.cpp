#include "needlesim/engines/explicit/path_needle.hpp"

#include <algorithm>
#include <cmath>

#include "needlesim/core/error.hpp"
#include "needlesim/engines/explicit/cohesive.hpp"
#include "needlesim/engines/explicit/solver.hpp"

namespace needlesim::explicit_fe {

using Eigen::Vector2d;
using Eigen::Vector3d;

NeedlePath::NeedlePath(const std::vector<Vector2d>& p, double before, double after, double ds) {
  if (p.size() < 2) throw Error("needle path: needs at least 2 points");
  for (std::size_t i = 1; i < p.size(); ++i)
    if (!(p[i].x() > p[i - 1].x())) throw Error("needle path: the x coordinates must increase along the path");
  if (!(ds > 0) || !(before >= 0) || !(after >= 0)) throw Error("needle path: bad extension or spacing");
  // the polyline with its straight extensions, and its cumulative arc length (0 at p[0])
  std::vector<Vector2d> v;
  const Vector2d t0 = (p[1] - p[0]).normalized(), t1 = (p.back() - p[p.size() - 2]).normalized();
  if (before > 0) v.push_back(p.front() - before * t0);
  v.insert(v.end(), p.begin(), p.end());
  if (after > 0) v.push_back(p.back() + after * t1);
  std::vector<double> s(v.size(), -before);
  for (std::size_t i = 1; i < v.size(); ++i) s[i] = s[i - 1] + (v[i] - v[i - 1]).norm();
  const double total = s.back() - s.front();
  const int n = std::max(1, static_cast<int>(std::ceil(total / ds)));
  hs_ = total / n;
  s0_ = s.front();
  q_.resize(n + 1);
  std::size_t j = 0;
  for (int k = 0; k <= n; ++k) {
    const double sk = k == n ? s.back() : s0_ + k * hs_;
    while (j + 2 < v.size() && s[j + 1] < sk) ++j;
    const double u = std::clamp((sk - s[j]) / (s[j + 1] - s[j]), 0.0, 1.0);
    q_[k] = v[j] + u * (v[j + 1] - v[j]);
  }
  t_.resize(n + 1);
  for (int k = 0; k <= n; ++k) t_[k] = (q_[std::min(k + 1, n)] - q_[std::max(k - 1, 0)]).normalized();
  // uniform x cells no wider than the narrowest sample segment (one cell start per segment at most)
  double dxMin = hs_;
  for (int k = 0; k < n; ++k) dxMin = std::min(dxMin, q_[k + 1].x() - q_[k].x());
  x0_ = q_.front().x();
  hx_ = std::max(dxMin, 1e-6 * hs_);
  const int cells = static_cast<int>(std::ceil((q_.back().x() - x0_) / hx_)) + 1;
  cell_.resize(cells);
  int k = 0;
  for (int c = 0; c < cells; ++c) {
    while (k < n - 1 && q_[k + 1].x() <= x0_ + c * hx_) ++k;
    cell_[c] = k;
  }
}

int NeedlePath::segmentAt(double x) const {
  const int n = static_cast<int>(q_.size()) - 1;
  const double r = (x - x0_) / hx_;
  if (!(r > 0)) return 0;
  const int c = std::min(static_cast<int>(r), static_cast<int>(cell_.size()) - 1);
  int k = cell_[c];
  while (k < n - 1 && q_[k + 1].x() <= x) ++k;
  return k;
}

bool NeedlePath::near(const Vector2d& x, double reach) const {
  const int k = segmentAt(x.x());
  const Vector2d e = q_[k + 1] - q_[k];
  const double y = q_[k].y() + e.y() * (x.x() - q_[k].x()) / e.x();
  return std::abs(x.y() - y) <= reach;
}

void NeedlePath::locate(double sigma, int& k, double& u) const {
  const int n = static_cast<int>(q_.size()) - 1;
  const double r = (sigma - s0_) / hs_;
  k = std::clamp(static_cast<int>(std::floor(r)), 0, n - 1);
  u = r - k;  // may lie outside [0, 1] beyond the ends: linear extrapolation of the end segment
}

Vector2d NeedlePath::point(double sigma) const {
  int k;
  double u;
  locate(sigma, k, u);
  return q_[k] + u * (q_[k + 1] - q_[k]);
}

Vector2d NeedlePath::tangent(double sigma) const {
  int k;
  double u;
  locate(sigma, k, u);
  u = std::clamp(u, 0.0, 1.0);
  return ((1 - u) * t_[k] + u * t_[k + 1]).normalized();
}

double NeedlePath::station(const Vector2d& x) const {
  const int n = static_cast<int>(q_.size()) - 1;
  // segment whose abscissa range holds x (the samples are x-monotone), then walk to the nearest one
  int k = segmentAt(x.x());
  double u = 0.0;
  int last = -1;
  for (int it = 0; it < 4 * n + 8; ++it) {
    const Vector2d e = q_[k + 1] - q_[k];
    u = (x - q_[k]).dot(e) / e.squaredNorm();
    if (u < 0.0 && k > 0 && last != k - 1) {
      last = k;
      --k;
    } else if (u > 1.0 && k < n - 1 && last != k + 1) {
      last = k;
      ++k;
    } else {
      break;
    }
  }
  if (k > 0 && k < n - 1) u = std::clamp(u, 0.0, 1.0);  // a concave corner: its vertex
  return s0_ + (k + u) * hs_;
}

std::vector<Vector2d> NeedlePath::offset(double d) const {
  std::vector<Vector2d> o(q_.size());
  for (std::size_t k = 0; k < q_.size(); ++k) o[k] = q_[k] + d * Vector2d(-t_[k].y(), t_[k].x());
  return o;
}

namespace {
needle::NeedlePose poseAt(const RigidNeedle& n, double sigma) {
  const Vector2d p = n.path->point(sigma), t = n.path->tangent(sigma);
  needle::NeedlePose pose;
  pose.axis = Vector3d(t.x(), t.y(), 0.0);
  pose.bevelSide = n.pathSide * Vector3d(-t.y(), t.x(), 0.0);
  pose.tip = Vector3d(p.x(), p.y(), 0.0) + (n.station - sigma) * pose.axis;
  return pose;
}
}  // namespace

needle::NeedlePose pathPose(const RigidNeedle& n, const Vector3d& x) {
  const double sigma = std::min(n.path->station(Vector2d(x.x(), x.y())), n.station);
  return poseAt(n, sigma);
}

bool pathPoseNear(const RigidNeedle& n, const Vector3d& x, needle::NeedlePose& pose) {
  if (!n.path->near(Vector2d(x.x(), x.y()), 4.0 * n.shape.radius)) return false;
  pose = pathPose(n, x);
  return true;
}

void placeOnPath(RigidNeedle& n, double station) {
  n.station = station;
  n.pose = poseAt(n, station);
}

LipOffsets pathLipOffsets(const RigidNeedle& n, const CohesiveInterface& c, const std::vector<double>& X,
                          const std::vector<double>& u, double sMin, double sMax) {
  LipOffsets o;
  for (int p = 0; p < c.pairs(); ++p) {
    const int a = c.node(p, 0), b = c.node(p, 1);
    const Vector2d xa(X[2 * a] + u[2 * a], X[2 * a + 1] + u[2 * a + 1]), xb(X[2 * b] + u[2 * b], X[2 * b + 1] + u[2 * b + 1]);
    const double sa = n.path->station(xa), sb = n.path->station(xb);
    if (sa < sMin || sa > sMax) continue;
    const double oa = (xa - n.path->point(sa)).dot(n.pathSide * n.path->normal(sa));
    const double ob = (xb - n.path->point(sb)).dot(n.pathSide * n.path->normal(sb));
    ++o.pairs;
    o.meanA += oa;
    o.meanB += ob;
    o.maxA = std::max(o.maxA, oa);
    o.minB = std::min(o.minB, ob);
  }
  if (o.pairs > 0) o.meanA /= o.pairs, o.meanB /= o.pairs;
  return o;
}

needle::SurfaceMesh pathNeedleOutline2D(const RigidNeedle& n, int samples) {
  needle::SurfaceMesh m;
  m.pointsPerCell = 2;
  const double R = n.shape.radius, L = n.shape.length;
  auto add = [&](double s, double a) {  // s along the path from the tip, a along the local bevelSide
    const double sigma = n.station + std::min(s, 0.0);
    const Vector2d p = n.path->point(sigma), nr = n.pathSide * n.path->normal(sigma);
    const Vector2d t = n.path->tangent(sigma);
    const Vector2d q = p + a * nr + std::max(s, 0.0) * t;
    m.points.insert(m.points.end(), {q.x(), q.y(), 0.0});
    return static_cast<int>(m.points.size() / 3 - 1);
  };
  using F = needle::NeedleFace;
  std::vector<std::pair<int, F>> loop;
  const double ta = std::tan(n.shape.tipAngle);
  const double sHeel = n.shape.tip == TipType::Bevel && ta < 1e12 ? -2.0 * R / ta : 0.0;
  for (int i = 0; i <= samples; ++i) loop.push_back({add(-L + L * i / samples, -R), i == samples ? F::Tip : F::OuterWall});
  for (int i = 0; i <= samples; ++i)
    loop.push_back({add(sHeel + (-L - sHeel) * i / samples, R), i == samples ? F::Base : F::OuterWall});
  for (std::size_t i = 0; i < loop.size(); ++i) {
    m.cells.insert(m.cells.end(), {loop[i].first, loop[(i + 1) % loop.size()].first});
    m.faces.push_back(loop[i].second);
  }
  return m;
}

}  // namespace needlesim::explicit_fe
