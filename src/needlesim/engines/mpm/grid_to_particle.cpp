// Grid to particle (seed 000 eq 4): the MUSL momentum remap, and the final
// pass: FLIP/PIC velocity, position, velocity gradient, deformation gradient
// and the stress update of each point, with the checks of its new state.
#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>

#include "needlesim/materials/stress_lanes.hpp"
#include "needlesim/engines/mpm/mpm_solver.hpp"
#include "needlesim/engines/mpm/near_bodies.hpp"
#include "needlesim/engines/mpm/pass_support.hpp"
#include "needlesim/engines/mpm/phase_clock.hpp"
#include "needlesim/engines/mpm/support_lanes.hpp"

namespace needlesim::mpm {

using namespace pass;

// MUSL: new particle velocity (FLIP/PIC blend) and scatter of its momentum.
// Per (i, j) the k sums of the grid velocities are formed first (tensor
// product, as in p2g).
template <int S>
MPM_CLONES void MpmSolver::g2pRemap() {
  const double invh = 1.0 / cfg_.h;
  const A4 O = {cfg_.origin.x(), cfg_.origin.y(), cfg_.origin.z(), 0.0};  // grid origin in lanes (support_lanes.hpp)
  const std::size_t n1 = static_cast<std::size_t>(nn_[1]), n2 = static_cast<std::size_t>(nn_[2]);
  constexpr std::size_t NR = 8;  // = nr_; a constant, so the k offsets fold into the addresses
  const double flip = cfg_.flip;
  const double* __restrict vel = vel_.data();
  double* __restrict rec = buf_[0].rec.data();
  const std::uint32_t* __restrict order = scatter_.order();
  const int lastColour = scatter_.lastColour();
  const std::uint32_t* cut = cutMask_.empty() ? nullptr : cutMask_.data();  // needle_cut.cpp
#pragma omp parallel num_threads(nthreads_)
  {
    const int T = teamSize(), t = threadId();
    double worked = 0;
    for (int colour = 0; colour <= lastColour; ++colour) {
    const double began = wallSeconds();
    const auto [q0, q1] = scatter_.colourShare(t, T, colour);
    for (std::size_t qi = q0; qi < q1; ++qi) {
      const std::size_t p = order[qi];
      if (qi + kPrefetchAhead < q1) prefetchRecord<5u>(&P_[order[qi + kPrefetchAhead]]);  // x, v, m | vg
      if (cut && cut[p]) {
        remapCutPoint(p, flip);  // the support across the needle's cut left out
        continue;
      }
      const auto [wx, wy, wz, dx, dy, dz, bx, by, bz] = lanes::stencil4<S>(P_[p].x, O, invh);  // weights in 4 lanes each
      const std::size_t off = static_cast<std::size_t>(body_[p]) * nodes_;
      A4 an = {0, 0, 0, 0}, ao = {0, 0, 0, 0};  // sum N v_new, sum N v_old
      for (int i = 0; i < S; ++i)
        for (int j = 0; j < S; ++j) {
          const std::size_t row =
              off + (static_cast<std::size_t>(bx + i) * n1 + static_cast<std::size_t>(by + j)) * n2 +
              static_cast<std::size_t>(bz);
          const double* __restrict v = vel + 8 * row;
          A4 sn = wz[0] * ld(v), so = wz[0] * ld(v + 4);
          for (int k = 1; k < S; ++k) {
            sn += wz[k] * ld(v + 8 * k);
            so += wz[k] * ld(v + 8 * k + 4);
          }
          const A4 wij = wx[i] * wy[j];
          an += wij * sn;
          ao += wij * so;
        }
      // eq 4: FLIP v + sum N (v_new - v_old), blended with PIC sum N v_new
      const double v0 = flip * (P_[p].v[0] + (an[0] - ao[0])) + (1 - flip) * an[0];
      const double v1 = flip * (P_[p].v[1] + (an[1] - ao[1])) + (1 - flip) * an[1];
      const double v2 = flip * (P_[p].v[2] + (an[2] - ao[2])) + (1 - flip) * an[2];
      P_[p].v[0] = v0;
      P_[p].v[1] = v1;
      P_[p].v[2] = v2;
      // The position update of g2pFinal uses the same sum (positions do not move in between).
      P_[p].vg[0] = an[0];
      P_[p].vg[1] = an[1];
      P_[p].vg[2] = an[2];
      const double m = P_[p].mass;
      const A4 q = {0.0, m * v0, m * v1, m * v2};  // lane 0 (mass) gets + 0
      for (int i = 0; i < S; ++i)
        for (int j = 0; j < S; ++j) {
          const A4 a = (wx[i] * wy[j]) * q;
          double* __restrict r = rec + NR * (off + (static_cast<std::size_t>(bx + i) * n1 +
                                                    static_cast<std::size_t>(by + j)) * n2 +
                                             static_cast<std::size_t>(bz));
          for (int k = 0; k < S; ++k, r += NR)
            add(r, wz[k] * a);
        }
    }
    worked += wallSeconds() - began;
    if (colour < lastColour && scatter_.colourHasPoints(colour)) {
#pragma omp barrier
    }
    }
    clock_.addBusy(PhaseClock::kRemap, t, worked);
  }
}

// Final pass: position from the updated grid velocity (eq 4), velocity
// gradient, deformation gradient and stress (update stress last). For USL the
// particle velocity is also updated here. Per point: the grid sums
// (gatherGridSums), the update (advancePoint), the checks of the new state
// (checkAdvanced); then the stresses of a chunk of points (stressChunk).
template <int S, bool Usl>
MPM_CLONES void MpmSolver::g2pFinal(double& ekOut, double& eiOut, double& vmaxOut) {
  const std::size_t np = size();
  const double invh = 1.0 / cfg_.h;
  const double ox = cfg_.origin.x(), oy = cfg_.origin.y(), oz = cfg_.origin.z();
  const A4 O = {ox, oy, oz, 0.0};  // grid origin in lanes (support_lanes.hpp)
  const std::size_t n1 = static_cast<std::size_t>(nn_[1]), n2 = static_cast<std::size_t>(nn_[2]);
  const double flip = cfg_.flip;
  const double dt = dt_;
  // vel_: v_new at 0-2, at 4-6 the remapped v* (MUSL) or the velocity before the update (USL).
  const double* __restrict vel = vel_.data();
  std::atomic<int> bad{0};
  std::atomic<std::size_t> badP{0};
  double ek = 0, ei = 0, vmax = 0;
  const double limEnd[3] = {nn_[0] - S + 1.0, nn_[1] - S + 1.0, nn_[2] - S + 1.0};  // last base node + 1
  const bool fbar = cfg_.fbar;
  const std::uint32_t* __restrict order = scatter_.order();
  const bool blocked = nthreads_ > 1;
  bool strayed = false;
  const std::uint32_t* cut = cutMask_.empty() ? nullptr : cutMask_.data();  // needle_cut.cpp
  // Two bodies: mark each point's cell at its new position for the next
  // step's NearBodies::mark (it zeroed the occupancy), instead of a pass over the points there.
  std::uint64_t* occ = cfg_.bodies > 1 ? nearBodies_.occupancy() : nullptr;
  const std::size_t occW = nearBodies_.words();
  // Equal shares of the scatter order (no colours: the grid is only read);
  // each point's new base node is checked against its block's bounds.
#pragma omp parallel num_threads(nthreads_) reduction(+ : ek, ei) reduction(max : vmax) reduction(|| : strayed)
  {
  const double began = wallSeconds();
  const int T = teamSize(), t = threadId();
  const std::size_t q0 = np * static_cast<std::size_t>(t) / static_cast<std::size_t>(T),
                    q1 = np * static_cast<std::size_t>(t + 1) / static_cast<std::size_t>(T);
  int lo[3] = {std::numeric_limits<int>::min(), std::numeric_limits<int>::min(), std::numeric_limits<int>::min()};
  int hi[3] = {std::numeric_limits<int>::max(), std::numeric_limits<int>::max(), std::numeric_limits<int>::max()};
  std::size_t block = 0, blockEnd = np;  // listed block of entry qi and its end
  if (blocked && q0 < q1) {
    block = scatter_.blockOf(q0);
    blockEnd = scatter_.blockEnd(block);
    scatter_.blockBounds(block, lo, hi);
  }
  // Chunks of points: the kinematics of the chunk, then its stresses, four
  // points of one material at a time on vector lanes (materials/stress_lanes.hpp).
  constexpr std::size_t kChunk = 32;
  for (std::size_t c0 = q0; c0 < q1; c0 += kChunk) {
    const std::size_t c1 = std::min(c0 + kChunk, q1);
    std::size_t ready[kChunk];
    std::size_t nready = 0;
    for (std::size_t qi = c0; qi < c1; ++qi) {
      const std::size_t p = order[qi];
      if (qi >= blockEnd) [[unlikely]] {
        while (qi >= scatter_.blockEnd(block)) ++block;
        blockEnd = scatter_.blockEnd(block);
        scatter_.blockBounds(block, lo, hi);
      }
      if (qi + kPrefetchAhead < q1) prefetchRecord<15u>(&P_[order[qi + kPrefetchAhead]]);  // the whole record
      const lanes::Stencil4<S> st = lanes::stencil4<S>(P_[p].x, O, invh);  // weights in 4 lanes each
      const std::size_t off = static_cast<std::size_t>(body_[p]) * nodes_;
      const GridSums g = cut && cut[p] ? cutGridSums(p, off, Usl) : gatherGridSums<S, Usl>(st, vel, off, n1, n2);
      const double J = advancePoint<Usl>(p, g, dt, flip);
      const double speed2 = P_[p].v[0] * P_[p].v[0] + P_[p].v[1] * P_[p].v[1] + P_[p].v[2] * P_[p].v[2];
      const double o[3] = {ox, oy, oz};
      const int cause =
          checkAdvanced<S>(p, J, speed2, o, invh, limEnd, n1, blocked ? lo : nullptr, hi, occ, occW, strayed);
      if (cause) {
        int expected = 0;
        if (bad.compare_exchange_strong(expected, cause)) badP = p;
        continue;
      }
      ek += 0.5 * P_[p].mass * speed2;
      if (!fbar) ready[nready++] = p;  // fbar: stress after the cell averages of det F (fbarStress)
    }
    stressChunk(ready, nready, ei, vmax);
  }
  clock_.addBusy(PhaseClock::kG2P, t, wallSeconds() - began);
  }
  if (strayed || bad.load()) scatter_.invalidate();  // sort again before the next scatter
  if (bad.load()) fail(badP.load(), bad.load());
  nearBodies_.setFresh(occ != nullptr);  // every point marked its cell
  if (fbar) fbarStress(ei, vmax);
  ekOut = ek;
  eiOut = ei;
  vmaxOut = vmax;
}

// g2pFinal: the sums of a point over its support, lanes = velocity component:
// sum N v_new and sum N v_old (USL only), the columns of the velocity gradient L.
struct MpmSolver::GridSums {
  A4 an, ao, Lx, Ly, Lz;
};

// g2pFinal: the sums of a point with support st in the grid velocities vel
// of its body (off = body * nodes). Tensor-product sums per (i, j):
// L_c0 += dx_i wy_j sum_k wz_k v_c, L_c1 += wx_i dy_j sum_k wz_k v_c,
// L_c2 += wx_i wy_j sum_k dz_k v_c.
template <int S, bool Usl>
[[gnu::always_inline]] inline MpmSolver::GridSums MpmSolver::gatherGridSums(const lanes::Stencil4<S>& st,
                                                                           const double* __restrict vel,
                                                                           std::size_t off, std::size_t n1,
                                                                           std::size_t n2) {
  constexpr bool usl = Usl;
  constexpr int go = usl ? 0 : 4;  // field of the velocity gradient
  const auto& [wx, wy, wz, dx, dy, dz, bx, by, bz] = st;
  A4 an = {0, 0, 0, 0}, ao = {0, 0, 0, 0};  // sum N v_new, sum N v_old (USL only)
  A4 Lx = {0, 0, 0, 0}, Ly = {0, 0, 0, 0}, Lz = {0, 0, 0, 0};  // columns of L (lanes: velocity component)
  for (int i = 0; i < S; ++i)
    for (int j = 0; j < S; ++j) {
      const std::size_t row = off + (static_cast<std::size_t>(bx + i) * n1 + static_cast<std::size_t>(by + j)) * n2 +
                              static_cast<std::size_t>(bz);
      const double* __restrict v = vel + 8 * row;
      // gradient field: v_new (USL, lanes 0-3) or the remapped v* (MUSL, lanes 4-7)
      // (the sums start from the k = 0 products, not from 0 + product:
      // the same values, without an add of zero and its register copy)
      const A4 vg0 = ld(v + go);
      A4 sw = wz[0] * vg0, sd = dz[0] * vg0, so = {0, 0, 0, 0};
      if constexpr (usl) so = wz[0] * ld(v + 4);
      for (int k = 1; k < S; ++k) {
        const A4 vg = ld(v + 8 * k + go);
        sw += wz[k] * vg;
        sd += dz[k] * vg;
        if constexpr (usl) so += wz[k] * ld(v + 8 * k + 4);
      }
      const A4 wij = wx[i] * wy[j];
      const A4 gxij = dx[i] * wy[j], gyij = wx[i] * dy[j];
      if constexpr (usl) {
        an += wij * sw;
        ao += wij * so;
      }
      Lx += gxij * sw;
      Ly += gyij * sw;
      Lz += wij * sd;
    }
  return {an, ao, Lx, Ly, Lz};
}

// g2pFinal: the sums of a point the needle's cut crosses (needle_cut.cpp).
MpmSolver::GridSums MpmSolver::cutGridSums(std::size_t p, std::size_t off, bool usl) const {
  double an[3], ao[3], L[9];
  gatherCutPoint(p, off, usl, an, ao, L);
  return {A4{an[0], an[1], an[2], 0.0}, A4{ao[0], ao[1], ao[2], 0.0}, A4{L[0], L[3], L[6], 0.0},
          A4{L[1], L[4], L[7], 0.0}, A4{L[2], L[5], L[8], 0.0}};
}

// g2pFinal: point p over the step dt from its grid sums g: the velocity
// (USL: FLIP blended with PIC by flip), the position (eq 4), F and the
// volume; returns det F.
template <bool Usl>
[[gnu::always_inline]] inline double MpmSolver::advancePoint(std::size_t p, const GridSums& g, double dt,
                                                             double flip) {
  const A4 &an = g.an, &ao = g.ao, &Lx = g.Lx, &Ly = g.Ly, &Lz = g.Lz;
  const double L[9] = {Lx[0], Ly[0], Lz[0], Lx[1], Ly[1], Lz[1], Lx[2], Ly[2], Lz[2]};
  double acc[3];
  if constexpr (Usl) {
    P_[p].v[0] = flip * (P_[p].v[0] + (an[0] - ao[0])) + (1 - flip) * an[0];
    P_[p].v[1] = flip * (P_[p].v[1] + (an[1] - ao[1])) + (1 - flip) * an[1];
    P_[p].v[2] = flip * (P_[p].v[2] + (an[2] - ao[2])) + (1 - flip) * an[2];
    for (int c = 0; c < 3; ++c) acc[c] = an[c];
  } else {
    acc[0] = P_[p].vg[0];
    acc[1] = P_[p].vg[1];
    acc[2] = P_[p].vg[2];
  }
  P_[p].x[0] += dt * acc[0];
  P_[p].x[1] += dt * acc[1];
  P_[p].x[2] += dt * acc[2];
  // F <- (I + dt L) F
  double Fn[9];
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
      Fn[3 * r + c] = P_[p].F[3 * r + c] + dt * (L[3 * r + 0] * P_[p].F[c] + L[3 * r + 1] * P_[p].F[3 + c] +
                                               L[3 * r + 2] * P_[p].F[6 + c]);
  for (int c = 0; c < 9; ++c) P_[p].F[c] = Fn[c];
  // det F by cofactors of the first row, the expression of Eigen's 3x3
  // determinant (same bits as Mat3::determinant, without the copy into a Mat3)
  const double J = Fn[0] * (Fn[4] * Fn[8] - Fn[5] * Fn[7]) - Fn[1] * (Fn[3] * Fn[8] - Fn[5] * Fn[6]) +
                   Fn[2] * (Fn[3] * Fn[7] - Fn[4] * Fn[6]);
  P_[p].vol = P_[p].vol0 * J;  // the next scatter's volume
  return J;
}

// g2pFinal: 0 when point p (det F = J, squared speed speed2) goes on after
// its update, else the cause for fail: 2 a velocity or position not finite,
// 1 J not positive or not finite, 3 its support at the new position leaves
// the grid (origin o, 1 / h invh; base nodes below limEnd). A point that goes
// on sets strayed when its base node leaves [baseLo, baseHi] (its block's
// bounds, blockBounds; no check without baseLo) and, two bodies, marks its cell in occ (occW words per body and row).
template <int S>
[[gnu::always_inline]] inline int MpmSolver::checkAdvanced(std::size_t p, double J, double speed2, const double* o,
                                                           double invh, const double* limEnd, std::size_t n1,
                                                           const int* baseLo, const int* baseHi,
                                                           std::uint64_t* occ, std::size_t occW, bool& strayed) {
  if (!std::isfinite(speed2) || !std::isfinite(P_[p].x[0] + P_[p].x[1] + P_[p].x[2])) return 2;
  if (!(J > 0.0) || !std::isfinite(J)) return 1;
  // Base node of the support at the new position (as weights<S>) in
  // 0 .. lim: floor(xs) in 0 .. lim, i.e. 0 <= xs < lim + 1.
  const double sh = S == 2 ? 0.0 : 0.5;
  const double xc[3] = {(P_[p].x[0] - o[0]) * invh, (P_[p].x[1] - o[1]) * invh, (P_[p].x[2] - o[2]) * invh};  // in cells
  const double xs[3] = {xc[0] - sh, xc[1] - sh, xc[2] - sh};
  int cause = 0;
  for (int d = 0; d < 3; ++d)
    if (!(xs[d] >= 0.0 && xs[d] < limEnd[d])) cause = 3;
  if (cause) return cause;
  if (baseLo)  // blocks (two or more threads)
    for (int d = 0; d < 3; ++d) {
      const int l = static_cast<int>(xs[d]);  // = the floor, xs >= 0
      strayed = strayed || l < baseLo[d] || l > baseHi[d];
    }
  if (occ) {  // as NearBodies::mark's own pass; threads meet at a row: atomic OR, skipped when set
    const grid::Cell c = grid::cellAt(xc[0], xc[1], xc[2], n1);
    std::uint64_t* w = occ + cellWord(c, body_[p], occW);
    const std::uint64_t bit = cellBit(c);
    if (!(__atomic_load_n(w, __ATOMIC_RELAXED) & bit)) __atomic_fetch_or(w, bit, __ATOMIC_RELAXED);
  }
  return 0;
}

// g2pFinal: the stresses of the nready points ready[] (in scatter order), four
// points of one material at a time on vector lanes where the law has them;
// their strain energy into ei, the largest wave plus point speed into vmax.
[[gnu::always_inline]] inline void MpmSolver::stressChunk(const std::size_t* ready, std::size_t nready, double& ei,
                                                          double& vmax) {
  for (std::size_t r = 0; r < nready;) {
    const std::size_t p0 = ready[r];
    const MpmMaterial& mat = mats_[mat_[p0]];
    if (!materials::lanes::hasLanes(mat.law)) {
      double W, c;
      stress(p0, defGrad(p0), W, c);
      const Point& q = P_[p0];
      ei += q.vol0 * W;
      vmax = std::max(vmax, c + std::sqrt(q.v[0] * q.v[0] + q.v[1] * q.v[1] + q.v[2] * q.v[2]));
      ++r;
      continue;
    }
    std::size_t g[4];
    int n = 0;
    while (r < nready && n < 4 && mat_[ready[r]] == mat_[p0]) g[n++] = ready[r++];
    for (int l = n; l < 4; ++l) g[l] = g[n - 1];  // idle lanes repeat the last point
    A4 Fl[9] = {}, sl[6] = {}, W = {}, wave = {};
    for (int c = 0; c < 9; ++c) Fl[c] = A4{P_[g[0]].F[c], P_[g[1]].F[c], P_[g[2]].F[c], P_[g[3]].F[c]};
    materials::lanes::hyperelasticStress4(mat.law, mat.density * cfg_.massScaling, Fl, sl, W, wave);
    for (int l = 0; l < n; ++l) {
      Point& q = P_[g[l]];
      for (int c = 0; c < 6; ++c) q.sig[c] = sl[c][l];
      ei += q.vol0 * W[l];
      vmax = std::max(vmax, wave[l] + std::sqrt(q.v[0] * q.v[0] + q.v[1] * q.v[1] + q.v[2] * q.v[2]));
    }
  }
}

void MpmSolver::stress(std::size_t p, const Mat3& F, double& W, double& wave) {
  const Mat3 sigma = evaluateStress(mats_[mat_[p]], F, cfg_.massScaling, W, wave);
  P_[p].sig[0] = sigma(0, 0);
  P_[p].sig[1] = sigma(1, 1);
  P_[p].sig[2] = sigma(2, 2);
  P_[p].sig[3] = sigma(0, 1);
  P_[p].sig[4] = sigma(1, 2);
  P_[p].sig[5] = sigma(0, 2);
}

// The MUSL remap (momentum of the new particle velocities into the cleared
// momentum lanes) for the set-up's shape.
void MpmSolver::remapMomentum() {
  if (cfg_.shape == Shape::Linear) g2pRemap<2>(); else g2pRemap<3>();
}

// The final gather for the set-up's shape and update scheme.
void MpmSolver::gridToParticle(double& ek, double& ei, double& vmax) {
  const bool lin = cfg_.shape == Shape::Linear;
  if (cfg_.update == Update::USL) {
    if (lin) g2pFinal<2, true>(ek, ei, vmax); else g2pFinal<3, true>(ek, ei, vmax);
  } else {
    if (lin) g2pFinal<2, false>(ek, ei, vmax); else g2pFinal<3, false>(ek, ei, vmax);
  }
}

}  // namespace needlesim::mpm
