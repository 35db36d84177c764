// The needle's cut in the material point method: the tissue parts along the
// strip of the plane through the needle axis normal to the bevel side that the
// needle has passed (from its base to where the tip reaches the plane, as wide
// as the needle; explicit 3D's pre-cut slit, as wide, runs through the sharp point),
// or (model.mpm.cut: edges) along the lower half of the needle's surface that
// the bevel's cutting edges have swept. A point does not reach the support
// nodes whose segment to it crosses the cut, and its weights over the nodes it reaches are
// renormalised (the visibility criterion of meshfree crack models, Belytschko
// et al. 1995, in the per-node field form of CRAMP, Nairn 2003): the two lips
// scatter to and gather from separate nodes, so the grid velocity field is
// discontinuous across the cut and the needle parts the tissue instead of
// dragging both lips as one field. Each lip meets the rigid needle through the
// unchanged contact (seed 000 eqs 14-21 on the grid, or eqs 22-24 with CFEMP).
// docs/models/mpm.md "Parting contact".
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdint>

#include "needlesim/engines/mpm/grid_kernels.hpp"
#include "needlesim/engines/mpm/mpm_solver.hpp"
#include "needlesim/needle/surface_mesh.hpp"

namespace needlesim::mpm {

// The support of a point that the cut crosses: the nodes it reaches (flat
// index without the body offset), the renormalised weights N' = N / sum N and
// their gradients grad N' = (grad N - N' grad sum N) / sum N over those nodes
// (a partition of unity again, so mass and momentum are conserved and the
// internal forces sum to zero).
struct MpmSolver::CutSupport {
  int n = 0;
  std::size_t node[27];
  double w[27];
  double g[27][3];
};

namespace {

// A renormalised support whose visible weights sum below this keeps all its
// nodes: a point with almost all of its support across the cut (the strip's
// edge) would otherwise get weights amplified without bound.
constexpr double kMinVisibleWeight = 0.25;

// The cut of a needle at its current position: the strip of the plane
// through the axis normal to the bevel side, as wide as the needle,
// {x : (x - c).n = 0, |(x - c).t| = |b| <= R, -length <= (x - c).e <= front(b)},
// c the axis point level with the tip moved cutAhead along the axis. A bevel
// parts the tissue where its face first reaches the plane, front(b) =
// sqrt(R^2 - b^2) / tan(alpha) ahead of the sharp point's plane; other tips
// at their tip plane.
//
// Along the edges: the face's outline is the needle's surface, so its edges
// cut the tissue along the lower half of that surface {r = R, a <= 0} (r, a, b
// from the axis, a along the bevel side) behind the face, a <= -R - s tan(alpha)
// (s from the sharp point's plane). What lies inside the outline is lifted by
// the face onto the needle (MpmSolver::bevelLipFloor), the tissue below stays,
// and the lift 2 sqrt(R^2 - b^2) vanishes where the cut meets the uncut tissue
// beside the needle, where the strip's lip would be torn by R.
struct CutStrip {
  Vec3 c, e, t, n;
  double halfWidth, length, cotBevel, onPlane;
  bool edges;
  double tanBevel;
  explicit CutStrip(const RigidBody& rb)
      : c(rb.axisPoint() + rb.cutAhead * rb.axis), e(rb.axis), n(rb.bevelSide), halfWidth(rb.radius),
        length(rb.length + rb.cutAhead),
        cotBevel(rb.tip == RigidBody::Tip::Bevel ? 1.0 / std::tan(rb.tipAngle) : 0.0), onPlane(1e-9 * rb.radius),
        edges(rb.cutAlongEdges), tanBevel(std::tan(rb.tipAngle)) {
    t = e.cross(n);
    t.normalize();
  }
  // Whether a point (rel to c) lies within a support's reach of the cut.
  bool near(const Vec3& rel, double reach) const {
    const double dp = rel.dot(n), s = rel.dot(e), b = rel.dot(t);
    if (edges) return std::hypot(dp, b) <= halfWidth + reach && s <= reach && s >= -length - reach;
    return std::abs(dp) <= reach && s <= reach + front(0.0) && s >= -length - reach && std::abs(b) <= halfWidth + reach;
  }
  // Whether the segment from x to y crosses the lower half of the needle's
  // surface behind the face: the roots of r(t) = R on it.
  bool crossesEdges(const Vec3& x, const Vec3& y) const {
    const Vec3 q = x - c, d = y - x;
    const double qa = q.dot(n), qb = q.dot(t), da = d.dot(n), db = d.dot(t), R = halfWidth;
    const double A = da * da + db * db, B = qa * da + qb * db, C = qa * qa + qb * qb - R * R;
    const double disc = B * B - A * C;
    if (!(A > 0) || disc < 0) return false;
    for (const double sign : {-1.0, 1.0}) {
      const double u = (-B + sign * std::sqrt(disc)) / A;
      const double a = qa + u * da, s = q.dot(e) + u * d.dot(e);  // s from the sharp point's plane
      if (u >= 0 && u <= 1 && a <= 0 && s >= -length && s * tanBevel <= -R - a) return true;
    }
    return false;
  }
  double front(double b) const { return cotBevel * std::sqrt(std::max(0.0, halfWidth * halfWidth - b * b)); }
  // The bevel side of the plane, a point on it (to rounding) included: a needle turned by
  // 180 deg sees the mirror image.
  bool bevelSide(double d) const { return d >= -onPlane; }
  // Whether the segment from the point x (side value dp) to the node y crosses the strip.
  bool crosses(const Vec3& x, double dp, const Vec3& y) const {
    if (edges) return crossesEdges(x, y);
    const double dn = (y - c).dot(n);
    if (bevelSide(dp) == bevelSide(dn)) return false;
    const Vec3 at = x + (dp / (dp - dn)) * (y - x);
    const double s = (at - c).dot(e), b = (at - c).dot(t);
    return std::abs(b) <= halfWidth && s <= front(b) && s >= -length;
  }
};

}  // namespace

std::size_t MpmSolver::cutPoints() const {
  return static_cast<std::size_t>(std::count_if(cutMask_.begin(), cutMask_.end(), [](std::uint32_t m) { return m != 0; }));
}

// Before p2g: per point, the support nodes across the cut of the parting
// needle at the current positions (the positions stay until g2pFinal).
void MpmSolver::planCut() {
  cutRigid_ = -1;
  for (std::size_t r = 0; r < rigids_.size() && cutRigid_ < 0; ++r)
    if (rigids_[r].kind == RigidBody::Kind::Needle && rigids_[r].tip == RigidBody::Tip::Bevel && rigids_[r].parting)
      cutRigid_ = static_cast<int>(r);  // a cone or a flat tip has no cutting edge: it pushes the tissue aside
  if (cutRigid_ < 0) {
    cutMask_.clear();  // the particle passes test for an empty mask
    return;
  }
  const CutStrip cut(rigids_[static_cast<std::size_t>(cutRigid_)]);
  const int S = cfg_.shape == Shape::Linear ? 2 : 3;
  const double invh = 1.0 / cfg_.h;
  const double reach = (S == 2 ? 1.0 : 1.5) * std::sqrt(3.0) * cfg_.h;  // farthest support node
  const std::size_t np = size();
  cutMask_.resize(np);
#pragma omp parallel for schedule(static) num_threads(nthreads_)
  for (std::size_t p = 0; p < np; ++p) {
    const Vec3 x = position(p), rel = x - cut.c;
    const double dp = rel.dot(cut.n);
    std::uint32_t mask = 0;
    if (cut.near(rel, reach)) {
      double w[3][3], dw[3][3];
      int base[3];
      for (int d = 0; d < 3; ++d) {
        const double xi = (x[d] - cfg_.origin[d]) * invh;
        base[d] = S == 2 ? grid::weights<2>(xi, invh, w[d], dw[d]) : grid::weights<3>(xi, invh, w[d], dw[d]);
      }
      double visible = 0.0;
      for (int i = 0; i < S; ++i)
        for (int j = 0; j < S; ++j)
          for (int k = 0; k < S; ++k) {
            const Vec3 y = cfg_.origin + cfg_.h * Vec3(base[0] + i, base[1] + j, base[2] + k);
            if (cut.crosses(x, dp, y))
              mask |= std::uint32_t{1} << (9 * i + 3 * j + k);
            else
              visible += w[0][i] * w[1][j] * w[2][k];
          }
      if (visible < kMinVisibleWeight) mask = 0;
    }
    cutMask_[p] = mask;
  }
}

void MpmSolver::cutSupport(std::size_t p, CutSupport& cs) const {
  const int S = cfg_.shape == Shape::Linear ? 2 : 3;
  const double invh = 1.0 / cfg_.h;
  const std::size_t n1 = static_cast<std::size_t>(nn_[1]), n2 = static_cast<std::size_t>(nn_[2]);
  double w[3][3], dw[3][3];
  int base[3];
  for (int d = 0; d < 3; ++d) {
    const double xi = (P_[p].x[d] - cfg_.origin[d]) * invh;
    base[d] = S == 2 ? grid::weights<2>(xi, invh, w[d], dw[d]) : grid::weights<3>(xi, invh, w[d], dw[d]);
  }
  const std::uint32_t mask = cutMask_[p];
  double sum = 0.0, gs[3] = {0.0, 0.0, 0.0};
  cs.n = 0;
  for (int i = 0; i < S; ++i)
    for (int j = 0; j < S; ++j)
      for (int k = 0; k < S; ++k) {
        if (mask & (std::uint32_t{1} << (9 * i + 3 * j + k))) continue;
        const int a = cs.n++;
        cs.node[a] = (static_cast<std::size_t>(base[0] + i) * n1 + static_cast<std::size_t>(base[1] + j)) * n2 +
                     static_cast<std::size_t>(base[2] + k);
        cs.w[a] = w[0][i] * w[1][j] * w[2][k];
        cs.g[a][0] = dw[0][i] * w[1][j] * w[2][k];
        cs.g[a][1] = w[0][i] * dw[1][j] * w[2][k];
        cs.g[a][2] = w[0][i] * w[1][j] * dw[2][k];
        sum += cs.w[a];
        for (int d = 0; d < 3; ++d) gs[d] += cs.g[a][d];
      }
  for (int a = 0; a < cs.n; ++a) {
    cs.w[a] /= sum;
    for (int d = 0; d < 3; ++d) cs.g[a][d] = (cs.g[a][d] - cs.w[a] * gs[d]) / sum;
  }
}

// p2g of a point the cut crosses (eqs 1-2 and the internal force, as
// scatterPoint, over the nodes it reaches).
void MpmSolver::scatterCutPoint(std::size_t p, bool needG) {
  CutSupport cs;
  cutSupport(p, cs);
  const Point& q = P_[p];
  const double m = q.mass, V = -q.vol;
  const double s[3][3] = {{q.sig[0], q.sig[3], q.sig[5]}, {q.sig[3], q.sig[1], q.sig[4]}, {q.sig[5], q.sig[4], q.sig[2]}};
  const std::size_t off = static_cast<std::size_t>(body_[p]) * nodes_;
  double* rec = buf_[0].rec.data();
  double* grad = buf_[0].grad.data();
  for (int a = 0; a < cs.n; ++a) {
    double* r = rec + 8 * (off + cs.node[a]);
    const double w = cs.w[a];
    const double* g = cs.g[a];
    r[grid::kM] += w * m;
    for (int c = 0; c < 3; ++c) {
      r[grid::kP + c] += w * m * q.v[c];
      r[grid::kF + c] += V * (s[c][0] * g[0] + s[c][1] * g[1] + s[c][2] * g[2]);
    }
    if (!needG) continue;
    double* gr = grad + 8 * (off + cs.node[a]);
    for (int c = 0; c < 3; ++c) gr[grid::kG + c] += m * g[c];
  }
}

// MUSL remap of a point the cut crosses (as g2pRemap over the nodes it reaches).
void MpmSolver::remapCutPoint(std::size_t p, double flip) {
  CutSupport cs;
  cutSupport(p, cs);
  const std::size_t off = static_cast<std::size_t>(body_[p]) * nodes_;
  double an[3] = {0, 0, 0}, ao[3] = {0, 0, 0};
  for (int a = 0; a < cs.n; ++a) {
    const double* v = &vel_[8 * (off + cs.node[a])];
    for (int c = 0; c < 3; ++c) {
      an[c] += cs.w[a] * v[c];
      ao[c] += cs.w[a] * v[4 + c];
    }
  }
  Point& q = P_[p];
  for (int c = 0; c < 3; ++c) {
    q.v[c] = flip * (q.v[c] + (an[c] - ao[c])) + (1 - flip) * an[c];  // eq 4
    q.vg[c] = an[c];
  }
  double* rec = buf_[0].rec.data();
  for (int a = 0; a < cs.n; ++a) {
    double* r = rec + 8 * (off + cs.node[a]);
    for (int c = 0; c < 3; ++c) r[grid::kP + c] += cs.w[a] * q.mass * q.v[c];
  }
}

// g2pFinal's sums of a point the cut crosses: sum N v_new, sum N v_old (usl)
// and the velocity gradient L (row major, L_cd = sum v_c dN/dx_d) of the
// gradient field (usl: v_new, lanes 0-2; musl: the remapped v*, lanes 4-6).
void MpmSolver::gatherCutPoint(std::size_t p, std::size_t off, bool usl, double* an, double* ao, double* L) const {
  CutSupport cs;
  cutSupport(p, cs);
  const int go = usl ? 0 : 4;
  std::fill_n(an, 3, 0.0);
  std::fill_n(ao, 3, 0.0);
  std::fill_n(L, 9, 0.0);
  for (int a = 0; a < cs.n; ++a) {
    const double* v = &vel_[8 * (off + cs.node[a])];
    for (int c = 0; c < 3; ++c) {
      an[c] += cs.w[a] * v[c];
      ao[c] += cs.w[a] * v[4 + c];
      for (int d = 0; d < 3; ++d) L[3 * c + d] += v[go + c] * cs.g[a][d];
    }
  }
}

// A parting bevel (rigid r) seen from the wall-side lip (the side of the cut
// opposite the bevel face, x): the lip passes under the needle's wall, led by
// the frictionless chisel ahead of the sharp point that explicit 3D uses, the
// ramp a = -R + s tan 30 deg (needle::kLipRampAngle), whose outward normal
// sin(30) e - cos(30) bevelSide replaces the bevel face's. The face's own
// normal would push that lip across the needle's path, to the bevel side, and
// drive it ahead of the tip. With the cut along the edges the tissue outside
// the needle's outline below the axis plane meets the face's edge, which runs
// along the outline: it gets the outline's normal, radial from the axis.
// Returns whether n was replaced.
bool MpmSolver::wallLipNormal(std::size_t r, const Vec3& x, Vec3& n) const {
  if (static_cast<int>(r) != cutRigid_) return false;
  const RigidBody& rb = rigids_[r];
  const Vec3 q = x - rb.axisPoint();
  const double a = q.dot(rb.bevelSide);
  if (rb.tip != RigidBody::Tip::Bevel || a >= -1e-9 * rb.radius) return false;
  if (rb.cutAlongEdges) {
    const Vec3 radial = q - q.dot(rb.axis) * rb.axis;
    if (radial.norm() < rb.radius) return false;
    n = radial.normalized();
    return true;
  }
  n = std::sin(needle::kLipRampAngle) * rb.axis - std::cos(needle::kLipRampAngle) * rb.bevelSide;
  return true;
}

// A bevel cutting along its edges (rigid r), seen from a point inside the
// needle's outline (|b| < R, a >= -sqrt(R^2 - b^2)) behind the sharp point: the
// face lifts it, as explicit 3D's face lifts its slit's lip
// (engines/explicit/cohesive_wedge.cpp): its floor is the face's plane
// a = -R - s tan(alpha) up to the upper outline a = sqrt(R^2 - b^2). The
// needle's own nearest facet would push the points beside the lower outline
// down, across the cut. xl: the point in NeedleSurface's frame (s along the
// axis from the sharp point's plane, a along bevelSide from the axis, b).
// Above the axis plane behind the face the needle's own surface is the floor
// and this returns false, as for points outside the outline or ahead of the
// sharp point. gap: signed (negative below the floor); nl: the floor's outward
// normal in that frame; onFace: the face (tip) or the outline.
bool MpmSolver::bevelLipFloor(std::size_t r, const Vec3& xl, double& gap, Vec3& nl, bool& onFace) const {
  if (static_cast<int>(r) != cutRigid_ || !rigids_[r].cutAlongEdges) return false;
  const RigidBody& rb = rigids_[r];
  const double R = rb.radius, s = xl.x(), a = xl.y(), b = xl.z();
  if (rb.tip != RigidBody::Tip::Bevel || std::abs(b) >= R || s > 0.0 || s < -rb.length) return false;
  const double w = std::sqrt(R * R - b * b), face = -R - s * std::tan(rb.tipAngle);
  onFace = face < w;
  if (a < -w || (!onFace && a >= 0.0)) return false;
  gap = a - std::min(face, w);
  nl = onFace ? Vec3(std::sin(rb.tipAngle), std::cos(rb.tipAngle), 0.0) : Vec3(0.0, 1.0, 0.0);
  return true;
}

// CFEMP (surfaceContact) of a point the cut crosses: the nodes it reaches
// (with the body offset) and their weights; returns their number.
int MpmSolver::cutSurfaceWeights(std::size_t p, std::size_t* node, double* w) const {
  CutSupport cs;
  cutSupport(p, cs);
  const std::size_t off = static_cast<std::size_t>(body_[p]) * nodes_;
  for (int a = 0; a < cs.n; ++a) {
    node[a] = off + cs.node[a];
    w[a] = cs.w[a];
  }
  return cs.n;
}

}  // namespace needlesim::mpm
