// Particle to grid (seed 000 eqs 1-3): mass, momentum and internal force of
// every material point into the shared grid, block colour by block colour
// (block_colouring.hpp); two bodies: the mass gradients near the other body;
// the nodal gap minima of the rigid grid contact (eq 22).
#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>

#include "needlesim/engines/mpm/mpm_solver.hpp"
#include "needlesim/engines/mpm/near_bodies.hpp"
#include "needlesim/engines/mpm/pass_support.hpp"
#include "needlesim/engines/mpm/phase_clock.hpp"
#include "needlesim/engines/mpm/support_lanes.hpp"

namespace needlesim::mpm {

using namespace pass;

// Thread t of T clears its share of the shared grid (inside a parallel region).
void MpmSolver::zeroGrid(int t, int T) {
  Buf& b = buf_[0];
  const auto part = [&](auto& v, double x) {
    const std::size_t n = v.size(), a = n * static_cast<std::size_t>(t) / static_cast<std::size_t>(T),
                      e = n * static_cast<std::size_t>(t + 1) / static_cast<std::size_t>(T);
    std::fill(v.begin() + static_cast<std::ptrdiff_t>(a), v.begin() + static_cast<std::ptrdiff_t>(e), x);
  };
  part(b.rec, 0.0);  // gmin: reset by gridUpdate, its only reader
  part(b.grad, 0.0);
}

namespace {
// Nodal gap minimum over the support of one point (eq 22) whose base node is
// at gmin. Out of line on purpose: inlined into p2g, GCC hoists the 27 node
// indices above the gap tests and so computes them for every point (~85
// instructions per point-step), though only the points near a needle (a few
// per cent) get here.
// gmat (null when every material takes the rigid body's friction): the
// material of the point of the smallest gap at each node, the first at a tie.
template <int S>
[[gnu::noinline]] void minGap(double* gmin, std::uint8_t* gmat, std::size_t sx, std::size_t sy, double gap,
                              std::uint8_t material) {
  for (int i = 0; i < S; ++i)
    for (int j = 0; j < S; ++j)
      for (int k = 0; k < S; ++k) {
        const std::size_t o = static_cast<std::size_t>(i) * sx + static_cast<std::size_t>(j) * sy + static_cast<std::size_t>(k);
        if (!(gap < gmin[o])) continue;
        gmin[o] = gap;
        if (gmat) gmat[o] = material;
      }
}
}  // namespace

// Cheap bound for the gap search: the signed distance to a needle is at
// least its distance to the shaft cylinder, r - R (the solid is an intersection).
struct MpmSolver::NeedleAxis {
  Vec3 c, e;
  double rmax2;
  bool needle;
};

// p2g: the shaft axis of each of the first 8 rigids, marked when it is a
// needle with grid contact, and the squared reach of the gap search around it.
[[gnu::always_inline]] inline std::array<MpmSolver::NeedleAxis, 8> MpmSolver::needleAxes(double gapReach) const {
  const int R = static_cast<int>(rigids_.size());
  std::array<NeedleAxis, 8> ax{};
  for (int r = 0; r < R && r < 8; ++r) {
    const RigidBody& rb = rigids_[static_cast<std::size_t>(r)];
    NeedleAxis& A = ax[static_cast<std::size_t>(r)];
    A.needle = rb.kind == RigidBody::Kind::Needle && !rb.surfaceContact;
    A.c = rb.axisPoint();
    A.e = rb.axis;
    A.rmax2 = (rb.radius + gapReach) * (rb.radius + gapReach);
  }
  return ax;
}

// Particle to grid: mass, momentum and internal force (scatterPoint), the
// gradient records near the other body, the gap minima of the rigids. Blocks
// of one colour touch disjoint nodes (blockBounds), so the threads add into
// one shared grid without races, colour by colour; each node's sums follow
// the colours, then the creation order within a block, on any team of two or
// more threads.
template <int S, bool Grad>
MPM_CLONES void MpmSolver::p2g() {
  const double invh = 1.0 / cfg_.h;
  const double ox = cfg_.origin.x(), oy = cfg_.origin.y(), oz = cfg_.origin.z();
  const A4 O = {ox, oy, oz, 0.0};  // grid origin in lanes (support_lanes.hpp)
  const std::size_t n1 = static_cast<std::size_t>(nn_[1]), n2 = static_cast<std::size_t>(nn_[2]);
  const int R = static_cast<int>(rigids_.size());
  const double gapReach = 2.0 * cfg_.h + rigidGap_;
  const std::array<NeedleAxis, 8> ax = needleAxes(gapReach);
  Buf& B = buf_[0];
  double* __restrict rec = B.rec.data();
  double* __restrict grad = B.grad.data();  // two bodies
  std::uint32_t* __restrict nearCell = nearCell_.data();  // two bodies
  const std::uint32_t* __restrict order = scatter_.order();
  const std::uint64_t* nearRows = nearBodies_.near();
  const std::uint64_t* near1Rows = nearBodies_.near1();
  const std::size_t nearW = nearBodies_.words();
  const bool gridClean = gridClean_;  // remapUpdate cleared the records it used
  gridClean_ = false;
  const int lastColour = scatter_.lastColour();
  std::atomic<int> busy{0};
  const std::uint32_t* cut = cutMask_.empty() ? nullptr : cutMask_.data();  // needle_cut.cpp
  const double start = wallSeconds(), cpuStart = cpuSeconds();
  double zeroed = start, cpuZeroed = cpuStart;
#pragma omp parallel num_threads(nthreads_)
  {
    const int T = teamSize(), t = threadId();
    if (!gridClean) {
      zeroGrid(t, T);
#pragma omp barrier
    }
    if (t == 0) {
      zeroed = wallSeconds();
      cpuZeroed = cpuSeconds();
    }
    bool scattered = false;
    double worked = 0;
    for (int colour = 0; colour <= lastColour; ++colour) {
    const double began = wallSeconds();
    const auto [q0, q1] = scatter_.colourShare(t, T, colour);
    scattered = scattered || q1 > q0;
    for (std::size_t qi = q0; qi < q1; ++qi) {
      const std::size_t p = order[qi];
      if (qi + kPrefetchAhead < q1) prefetchRecord<3u>(&P_[order[qi + kPrefetchAhead]]);  // x, v, m, V | sigma
      const lanes::Stencil4<S> st = lanes::stencil4<S>(P_[p].x, O, invh);  // weights in 4 lanes each
      const double xp[3] = {P_[p].x[0], P_[p].x[1], P_[p].x[2]};
      // Two bodies: the normal and gap lanes matter only at nodes that both
      // bodies reach, i.e. for points with the other body within 3 cells.
      bool needG = false;
      if constexpr (Grad) {
        const grid::Cell c = grid::cellAt((xp[0] - ox) * invh, (xp[1] - oy) * invh, (xp[2] - oz) * invh, n1);
        const std::size_t w = cellWord(c, 1 - body_[p], nearW);  // the other body's bits
        needG = (nearRows[w] & cellBit(c)) != 0;
        // the penalty contact's candidates (penaltyForces): the other body in the 27 cells around
        const bool cand = needG && (near1Rows[w] & cellBit(c)) != 0;
        nearCell[p] = cand ? static_cast<std::uint32_t>(c.row * n2 + c.k) : kNotNear;
      }
      if (cut && cut[p])
        scatterCutPoint(p, Grad && needG);  // the support across the needle's cut left out
      else
        scatterPoint<S, Grad>(p, st, needG, rec, grad, n1, n2);
      // Gap of this particle to each rigid body (eq 22), kept as a nodal minimum.
      for (int r = 0; r < R; ++r) {
        const RigidBody& rb = rigids_[static_cast<std::size_t>(r)];
        if (rb.surfaceContact) continue;  // CFEMP: particle-to-surface search instead
        if (r < 8 && ax[static_cast<std::size_t>(r)].needle) {
          const NeedleAxis& A = ax[static_cast<std::size_t>(r)];
          // Scalar on purpose: a vectorised form packs rel through the stack and
          // stalls on store forwarding in this, the most frequent, branch.
          const double r0 = xp[0] - A.c.x(), r1 = xp[1] - A.c.y(), r2 = xp[2] - A.c.z();
          const double s = r0 * A.e.x() + r1 * A.e.y() + r2 * A.e.z();
          if (r0 * r0 + r1 * r1 + r2 * r2 - s * s > A.rmax2) continue;
        }
        const double gap = rb.distance(Vec3(xp[0], xp[1], xp[2]), nullptr, nullptr);
        if (gap > gapReach) continue;
        const std::size_t base = static_cast<std::size_t>(r) * nodes_ + (st.bx * n1 + st.by) * n2 + st.bz;
        minGap<S>(B.gmin.data() + base, B.gmat.empty() ? nullptr : B.gmat.data() + base, n1 * n2, n2, gap, mat_[p]);
      }
    }
    worked += wallSeconds() - began;
    if (colour < lastColour && scatter_.colourHasPoints(colour)) {
#pragma omp barrier
    }
    }
    clock_.addBusy(PhaseClock::kScatter, t, worked);
    if (scattered) busy.fetch_add(1, std::memory_order_relaxed);
  }
  scatterThreads_ = busy.load();
  clock_.add(PhaseClock::kZeroGrid, start, cpuStart, zeroed, cpuZeroed);
  clock_.add(PhaseClock::kScatter, zeroed, cpuZeroed, wallSeconds(), cpuSeconds());
}

// p2g of point p over its support st: mass and momentum (eqs
// 1-2) and the internal force -V sigma : grad N into the records of its body;
// with needG (two bodies, the other one near) the gradient record too: the
// mass gradient (the pair contact's surface normal). Tensor-product form: for a node (i, j, k) w = wx_i wy_j wz_k and
// grad N = (dx_i wy_j wz_k, wx_i dy_j wz_k, wx_i wy_j dz_k), so every record
// entry is wz_k a_ij + dz_k b_ij with a, b formed once per (i, j); the k loop
// is a fixed-length vector update of one cache line.
template <int S, bool Grad>
[[gnu::always_inline]] inline void MpmSolver::scatterPoint(std::size_t p, const lanes::Stencil4<S>& st,
                                                           bool needG,
                                                           double* __restrict rec, double* __restrict grad,
                                                           std::size_t n1, std::size_t n2) {
  constexpr std::size_t NR = 8;
  const auto& [wx, wy, wz, dx, dy, dz, bx, by, bz] = st;
  const double m = P_[p].mass;
  const A4 q = {m, m * P_[p].v[0], m * P_[p].v[1], m * P_[p].v[2]};  // eqs 1-2
  const double V = -P_[p].vol;  // -V sigma : grad N is the internal force
  const double s00 = V * P_[p].sig[0], s11 = V * P_[p].sig[1], s22 = V * P_[p].sig[2];
  const double s01 = V * P_[p].sig[3], s12 = V * P_[p].sig[4], s02 = V * P_[p].sig[5];
  const double z0 = opaqueZero();
  const A4 S0 = {s00, s01, s02, z0}, S1 = {s01, s11, s12, z0}, S2 = {s02, s12, s22, z0};  // rows of -V sigma
  const std::size_t off = static_cast<std::size_t>(body_[p]) * nodes_;
  for (int i = 0; i < S; ++i)
    for (int j = 0; j < S; ++j) {
      const A4 wij = wx[i] * wy[j];
      const A4 gxij = dx[i] * wy[j], gyij = wx[i] * dy[j];
      const std::size_t node = off + (static_cast<std::size_t>(bx + i) * n1 +
                                      static_cast<std::size_t>(by + j)) * n2 +
                               static_cast<std::size_t>(bz);
      double* __restrict r = rec + NR * node;
      const A4 a0 = wij * q;
      const A4 a1 = gxij * S0 + gyij * S1;
      const A4 b1 = wij * S2;
      if (Grad && needG) {
        // gradient record: mass gradient (3)
        const A4 a2 = {m * gxij[0], m * gyij[0], 0.0, z0};
        const A4 b2 = {z0, z0, m * wij[0], z0};
        double* __restrict g = grad + 8 * node;
        for (int k = 0; k < S; ++k, r += NR, g += 8) {
          add(r, wz[k] * a0);
          add(r + 4, wz[k] * a1 + dz[k] * b1);
          add(g, wz[k] * a2 + dz[k] * b2);
        }
      } else {
        for (int k = 0; k < S; ++k, r += NR) {
          add(r, wz[k] * a0);
          add(r + 4, wz[k] * a1 + dz[k] * b1);
        }
      }
    }
}

// Particle to grid for the set-up's shape and bodies; two bodies: the cells
// near the other body first (near_bodies.hpp).
void MpmSolver::particleToGrid() {
  const bool lin = cfg_.shape == Shape::Linear;
  if (cfg_.bodies > 1) {
    nearBodies_.mark(positions(), body_.data(), nn_);
    if (lin) p2g<2, true>(); else p2g<3, true>();
  } else {
    if (lin) p2g<2, false>(); else p2g<3, false>();
  }
}

}  // namespace needlesim::mpm
