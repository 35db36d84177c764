// CFEMP: particle-to-surface contact of the rigid needle (seed 000 eqs
// 22-24), the needle's surface triangulated by needle/surface_mesh with a
// bucket grid (cfemp_contact.hpp), and the contact impulses on the grid.
#include "needlesim/engines/mpm/cfemp_contact.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "needlesim/contact/coulomb.hpp"
#include "needlesim/core/error.hpp"
#include "needlesim/engines/mpm/mpm_solver.hpp"
#include "needlesim/engines/mpm/pass_support.hpp"
#include "needlesim/needle/surface_mesh.hpp"

namespace needlesim::mpm {

using pass::kInf;
using grid::kM;

// Closest point of triangle (a, b, c) to p (Ericson, Real-Time Collision Detection 5.1.5).
Vec3 closestOnTriangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + (d1 / (d1 - d3)) * ab;
  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + (d2 / (d2 - d6)) * ac;
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) return b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b);
  const double den = 1.0 / (va + vb + vc);
  return a + ab * (vb * den) + ac * (vc * den);
}

// The FE needle surface of seed 000 section 4.3 (cylinder, 20 deg bevel) from
// needle/surface_mesh in the needle's own frame; buckets hold every triangle
// whose box, grown by the contact reach, overlaps them.
void NeedleSurface::build(const RigidBody& rb, double dp, double gap, double h) {
  if (rb.kind != RigidBody::Kind::Needle) throw Error("mpm: CFEMP contact needs a needle body");
  needle::NeedleShape sh;
  sh.radius = rb.radius;
  sh.length = rb.length;
  sh.tip = rb.tip == RigidBody::Tip::Bevel ? TipType::Bevel : rb.tip == RigidBody::Tip::Conical ? TipType::Conical : TipType::Blunt;
  sh.tipAngle = rb.tip == RigidBody::Tip::Blunt ? 0.5 * std::numbers::pi : rb.tipAngle;
  needle::NeedlePose pose;  // tip at 0, axis x, bevelSide y (sharp point at -R y)
  const double de = rb.elementSize > 0 ? rb.elementSize : dp;
  const int nCirc = std::max(16, static_cast<int>(std::ceil(2 * std::numbers::pi * rb.radius / (0.25 * de))));
  const int nAxial = std::max(4, static_cast<int>(std::ceil(rb.length / de)));
  const needle::SurfaceMesh m = needle::needleSurface3D(sh, pose, nCirc, nAxial);
  NeedleSurface& S = *this;
  auto P = [&](int i) { return Vec3(m.points[3 * i], m.points[3 * i + 1], m.points[3 * i + 2]); };
  const std::size_t nt = m.faces.size();
  for (std::size_t t = 0; t < nt; ++t) {
    const Vec3 a = P(m.cells[3 * t]), b = P(m.cells[3 * t + 1]), c = P(m.cells[3 * t + 2]);
    Vec3 n = (b - a).cross(c - a);
    if (!(n.norm() > 0)) continue;
    S.a.push_back(a);
    S.b.push_back(b);
    S.c.push_back(c);
    S.n.push_back(n.normalized());
    S.tip.push_back(m.faces[t] == needle::NeedleFace::Tip ? 1 : 0);
  }
  S.reach = 0.5 * rb.elementSize + gap + 0.5 * h;  // gap rule + a margin for the motion
  S.cell = std::max(0.5 * rb.radius, 0.25 * h);
  Vec3 lo = Vec3::Constant(kInf), hi = Vec3::Constant(-kInf);
  for (std::size_t t = 0; t < S.a.size(); ++t)
    for (const Vec3* v : {&S.a[t], &S.b[t], &S.c[t]}) {
      lo = lo.cwiseMin(*v);
      hi = hi.cwiseMax(*v);
    }
  S.lo = lo - Vec3::Constant(S.reach);
  for (int d = 0; d < 3; ++d) S.dim[d] = static_cast<int>(std::ceil((hi[d] + S.reach - S.lo[d]) / S.cell)) + 1;
  const std::size_t nb = static_cast<std::size_t>(S.dim[0]) * S.dim[1] * S.dim[2];
  std::vector<std::vector<int>> lists(nb);
  for (std::size_t t = 0; t < S.a.size(); ++t) {
    const Vec3 tl = S.a[t].cwiseMin(S.b[t]).cwiseMin(S.c[t]) - Vec3::Constant(S.reach);
    const Vec3 th = S.a[t].cwiseMax(S.b[t]).cwiseMax(S.c[t]) + Vec3::Constant(S.reach);
    int i0[3], i1[3];
    for (int d = 0; d < 3; ++d) {
      i0[d] = std::max(0, static_cast<int>((tl[d] - S.lo[d]) / S.cell));
      i1[d] = std::min(S.dim[d] - 1, static_cast<int>((th[d] - S.lo[d]) / S.cell));
    }
    for (int i = i0[0]; i <= i1[0]; ++i)
      for (int j = i0[1]; j <= i1[1]; ++j)
        for (int k = i0[2]; k <= i1[2]; ++k)
          lists[(static_cast<std::size_t>(i) * S.dim[1] + j) * S.dim[2] + k].push_back(static_cast<int>(t));
  }
  S.start.assign(nb + 1, 0);
  for (std::size_t b = 0; b < nb; ++b) S.start[b + 1] = S.start[b] + static_cast<int>(lists[b].size());
  S.items.clear();
  for (const auto& l : lists) S.items.insert(S.items.end(), l.begin(), l.end());
}

// The facet nearest to xl (the needle's frame) and the gap to it, signed by
// the facet that sees xl most from outside; facet -1 outside the buckets or
// with no facet in xl's bucket. radius: the needle's (the facet ranking).
NeedleSurface::Hit NeedleSurface::nearest(const Vec3& xl, double radius) const {
  const NeedleSurface& Sf = *this;
  int c[3];
  bool in = true;
  for (int d = 0; d < 3 && in; ++d) {
    const double u = (xl[d] - Sf.lo[d]) / Sf.cell;
    in = u >= 0 && u < Sf.dim[d];
    c[d] = in ? static_cast<int>(u) : 0;
  }
  if (!in) return {};
  const std::size_t bkt = (static_cast<std::size_t>(c[0]) * Sf.dim[1] + c[1]) * Sf.dim[2] + c[2];
  // Nearest facet; the gap is the distance, signed by the facet that
  // sees the particle most from outside (at a shared edge or vertex; the
  // needle is convex): the normal component alone put particles ahead
  // of a sharp apex in contact far too early. At a tie between a tip
  // facet and a wall facet (the bevel rim, its sharp point) the facet
  // that will sweep the particle gives the normal: a wall facet for a
  // particle outside the cylinder radius (the wall passes it), a tip
  // facet inside it (the tip face pushes it aside). Picking the tip
  // facet for every particle ahead of the sharp point pushed points
  // lying outside the radius across the needle's path, so the tissue
  // was driven ahead of the bevel instead of parting.
  const bool outside = xl.y() * xl.y() + xl.z() * xl.z() >= radius * radius;
  double best = kInf, signDot = -kInf, bestDot = -kInf;
  int bt = -1, bestRank = -1;
  for (int it = Sf.start[bkt]; it < Sf.start[bkt + 1]; ++it) {
    const int t = Sf.items[static_cast<std::size_t>(it)];
    const Vec3 xc = closestOnTriangle(xl, Sf.a[t], Sf.b[t], Sf.c[t]);  // foot of the perpendicular
    const double d2 = (xl - xc).squaredNorm();
    const double dot = (xl - xc).dot(Sf.n[t]);
    const int rank = outside && Sf.tip[static_cast<std::size_t>(t)] ? 0 : 1;  // the sweeping facet first
    const double tol = 1e-9 * best + 1e-24;
    if (d2 < best - tol) {
      best = d2;
      signDot = dot;
    } else if (d2 <= best + tol) {
      best = std::min(best, d2);
      signDot = std::max(signDot, dot);
      if (rank < bestRank || (rank == bestRank && dot <= bestDot)) continue;
    } else {
      continue;
    }
    bt = t;
    bestRank = rank;
    bestDot = dot;
  }
  const double gap = std::copysign(std::sqrt(best), signDot);
  return {bt, gap};
}

// CFEMP pairs of rigid r (eq 22): the particles within the gap of the
// needle's nearest facet, with that facet's normal and part.
void MpmSolver::findSurfacePairs(std::size_t r) {
  const RigidBody& rb = rigids_[r];
  const NeedleSurface& Sf = surf_[r];
  const Vec3 e = rb.axis, ys = rb.bevelSide, zs = e.cross(ys);
  const Vec3 c0 = rb.axisPoint();  // the surface's origin (NeedleSurface::build)
  pairs_.clear();
  const double limit = 0.5 * rb.elementSize + rigidGap_;  // eq 22: (d_e + d_p)/2
  for (std::size_t p = 0; p < size(); ++p) {
    const Vec3 q(P_[p].x[0] - c0.x(), P_[p].x[1] - c0.y(), P_[p].x[2] - c0.z());
    const Vec3 xl(q.dot(e), q.dot(ys), q.dot(zs));
    double floorGap = 0.0;
    Vec3 fl;
    bool onFace = false;
    if (bevelLipFloor(r, xl, floorGap, fl, onFace)) {  // a bevel cutting along its edges lifts what its outline holds
      if (floorGap < limit) pairs_.push_back({p, Vec3(fl.x() * e + fl.y() * ys + fl.z() * zs), onFace});
      continue;
    }
    const NeedleSurface::Hit hit = Sf.nearest(xl, rb.radius);
    if (hit.facet < 0 || !(hit.gap < limit)) continue;
    const Vec3& nl = Sf.n[static_cast<std::size_t>(hit.facet)];
    const bool tipFacet = Sf.tip[static_cast<std::size_t>(hit.facet)] != 0;
    Vec3 n(nl.x() * e + nl.y() * ys + nl.z() * zs);
    if (tipFacet) wallLipNormal(r, position(p), n);  // a parting bevel: the wall-side lip meets the chisel
    pairs_.push_back({p, n, tipFacet});
  }
}


// Particle-to-surface contact (seed 000 eqs 22-24) for the rigid needle with
// prescribed motion (m_c -> infinity in eq 23): a particle whose gap to the
// nearest facet is below (d_e + d_p)/2 (eq 22) and that approaches it gets the
// normal impulse that makes its grid-interpolated normal velocity equal to the
// needle's (eq 23), and a Coulomb tangential impulse, sticking up to mu times
// the normal one (as eqs 19-21). The impulse is spread to the nodes as
// N_Ip dp / m_I, which changes the interpolated velocity by dp / m_p with the
// equivalent mass 1/m_p = sum N_Ip^2 / m_I of eq 24. first: detect the pairs
// and record the force (after eq 3); otherwise reapply them to the remapped
// MUSL field. Serial: the contacts are a thin shell of particles.
template <int S>
void MpmSolver::surfaceContact(bool first) {
  const std::size_t R = rigids_.size();
  const double invh = 1.0 / cfg_.h;
  const double ox = cfg_.origin.x(), oy = cfg_.origin.y(), oz = cfg_.origin.z();
  const std::size_t n1 = static_cast<std::size_t>(nn_[1]), n2 = static_cast<std::size_t>(nn_[2]);
  const std::size_t NR = static_cast<std::size_t>(nr_);
  const Buf& G = buf_[0];
  const int lane = first ? 0 : 4;
  const double dt = dt_;
  for (std::size_t r = 0; r < R; ++r) {
    const RigidBody& rb = rigids_[r];
    if (!rb.surfaceContact) continue;
    if (first) findSurfacePairs(r);
    Vec3 ftot = Vec3::Zero(), ftip = Vec3::Zero(), fsh = Vec3::Zero();
    int count = 0;
    for (const SurfacePair& pr : pairs_) {
      const std::size_t p = pr.p;
      // the support nodes (with the body offset) and weights; the nodes across
      // the needle's cut left out (needle_cut.cpp)
      std::size_t node[27];
      double wn[27];
      int nn = 0;
      if (!cutMask_.empty() && cutMask_[p]) {
        nn = cutSurfaceWeights(p, node, wn);
      } else {
        const auto [wx, wy, wz, dx, dy, dz, bx, by, bz] = grid::stencil<S>(P_[p].x, ox, oy, oz, invh);
        const std::size_t off = static_cast<std::size_t>(body_[p]) * nodes_;
        for (int i = 0; i < S; ++i)
          for (int j = 0; j < S; ++j)
            for (int k = 0; k < S; ++k, ++nn) {
              node[nn] = off + (static_cast<std::size_t>(bx + i) * n1 + static_cast<std::size_t>(by + j)) * n2 +
                         static_cast<std::size_t>(bz + k);
              wn[nn] = wx[i] * wy[j] * wz[k];
            }
      }
      Vec3 vp = Vec3::Zero();
      double inv = 0.0;  // eq 24: 1/m_p = sum N^2 / m_I
      for (int a = 0; a < nn; ++a) {
        const double m = G.rec[NR * node[a] + kM];
        if (!(m > 0)) continue;
        const double* v = &vel_[8 * node[a] + static_cast<std::size_t>(lane)];
        vp += wn[a] * Vec3(v[0], v[1], v[2]);
        inv += wn[a] * wn[a] / m;
      }
      if (!(inv > 0)) continue;
      const double mp = 1.0 / inv;
      const Vec3 rel = vp - rb.velocity;  // v_p - v_c
      const double vn = rel.dot(pr.n);
      if (vn >= 0.0) continue;  // separating
      Vec3 dp = -mp * vn * pr.n;  // eq 23 times dt (m_c -> infinity)
      const Vec3 rt = rel - vn * pr.n;
      const double st = rt.norm();
      const double mu = pr.tip ? rb.tipFriction : rb.friction;
      if (st > 0) dp -= contact::coulombScale(st, -mu * vn) * mp * rt;  // Coulomb, as eqs 19-21
      for (int a = 0; a < nn; ++a) {
        const double m = G.rec[NR * node[a] + kM];
        if (!(m > 0)) continue;
        const double f = wn[a] / m;
        const std::uint8_t mask = bounds_.fixMask[node[a] % nodes_];
        double* v = &vel_[8 * node[a] + static_cast<std::size_t>(lane)];
        for (int c = 0; c < 3; ++c)
          if (!(mask & (1 << c))) v[c] += f * dp[c];
      }
      ++count;
      if (first) {
        ftot -= dp / dt;
        (pr.tip ? ftip : fsh) -= dp / dt;
      }
    }
    if (first) {
      rforce_[r].total = ftot;
      rforce_[r].tip = ftip;
      rforce_[r].shaft = fsh;
      rforce_[r].contactNodes = count;
    }
  }
}

void MpmSolver::cfempContact(bool first) {
  if (cfg_.shape == Shape::Linear)
    surfaceContact<2>(first);
  else
    surfaceContact<3>(first);
}

}  // namespace needlesim::mpm
