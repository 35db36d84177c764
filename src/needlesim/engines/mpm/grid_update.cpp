// The grid update (seed 000 eq 3 with gravity and the dashpots of
// grid_boundaries.hpp), the rigid grid contact of the needle or a plane at the
// nodes within the eq 22 gap (eqs 14-21 with m_rigid -> infinity), the fixed
// velocity components, the force on each rigid body, and the same contact on
// the MUSL-remapped velocities (remapUpdate).
#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>

#include "needlesim/contact/coulomb.hpp"
#include "needlesim/engines/mpm/mpm_solver.hpp"
#include "needlesim/engines/mpm/near_bodies.hpp"
#include "needlesim/engines/mpm/pass_support.hpp"
#include "needlesim/engines/mpm/phase_clock.hpp"
#include "needlesim/engines/mpm/support_lanes.hpp"

namespace needlesim::mpm {

using namespace pass;

namespace {

// Rigid body with prescribed motion: eq 28 in the limit m_tissue/m_needle -> 0.
// Returns the impulse given to the tissue (zero when separating).
inline Vec3 rigidContact(double m, double* v, const Vec3& n, const Vec3& vr, double mu) {
  const Vec3 rel(vr.x() - v[0], vr.y() - v[1], vr.z() - v[2]);
  const double vn = rel.dot(n);
  if (vn <= 0.0) return Vec3::Zero();  // eq 14
  Vec3 dv = vn * n;                    // eq 15
  const Vec3 rt = rel - vn * n;
  const double st = rt.norm();
  if (st > 0) dv += contact::coulombScale(st, mu * vn) * rt;  // eqs 19-21
  for (int c = 0; c < 3; ++c) v[c] += dv[c];
  return m * dv;
}

// Rows [first, last) of thread t of a team of T: equal shares of the work
// whose cumulative sum over the rows is cum (cum[q]: work of the rows before q).
inline std::pair<std::size_t, std::size_t> rowShare(const std::vector<std::uint64_t>& cum, int t, int T) {
  const std::uint64_t W = cum.back();
  const auto bound = [&](int u) -> std::size_t {
    if (u <= 0) return 0;
    if (u >= T) return cum.size() - 1;
    const std::uint64_t target = W * static_cast<std::uint64_t>(u) / static_cast<std::uint64_t>(T);
    return static_cast<std::size_t>(std::lower_bound(cum.begin(), cum.end(), target) - cum.begin());
  };
  return {bound(t), bound(t + 1)};
}

// The node kernels of the grid passes in four lanes: an AVX clone (no FMA, so
// no contraction: the roundings of the scalar code) and a baseline one.
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && !defined(NEEDLESIM_MPM_NO_CLONES)
#define MPM_AVX_CLONES __attribute__((target_clones("avx", "default")))
#else
#define MPM_AVX_CLONES
#endif

// eq 3 (+ gravity g, dashpot d) on n consecutive nodes of one body: records r
// (8 per node, as p2g), velocities v (8 per node), dashpots d (3 per node):
// v_new = (p + (f + m g) dt) / (m + d dt) and v_old = p / m, the pad lanes
// 0 / m = 0; nodes without mass get zero velocities. musl: clear the momentum
// lanes for the remap. fix (null: applied later, after contact): fixed
// velocity components per node.
MPM_AVX_CLONES void eq3Nodes(double* r, double* v, const double* d, std::size_t n, double dt,
                             const double* g, bool musl, const std::uint8_t* fix) {
  const double z = opaqueZero();
  const A4 grav = {g[0], g[1], g[2], z}, zero = {z, z, z, z};
  for (std::size_t k = 0; k < n; ++k, r += 8, v += 8, d += 3) {
    const double m = r[kM];
    if (!(m > 0)) {
      *reinterpret_cast<A4*>(v) = zero;
      *reinterpret_cast<A4*>(v + 4) = zero;
      continue;
    }
    const A4 p = {r[kP], r[kP + 1], r[kP + 2], z}, f = {r[kF], r[kF + 1], r[kF + 2], z};
    const A4 dd = {d[0], d[1], d[2], z};
    const A4 mm = {m, m, m, m};
    *reinterpret_cast<A4*>(v + 4) = p / mm;
    *reinterpret_cast<A4*>(v) = (p + (f + mm * grav) * dt) / (mm + dd * dt);
    if (musl) r[kP] = r[kP + 1] = r[kP + 2] = 0.0;  // the momentum lanes take the MUSL remap (g2pRemap)
    if (fix && fix[k])
      for (int c = 0; c < 3; ++c)
        if (fix[k] & (1 << c)) v[c] = 0.0;
  }
}

// The remapped velocity v* = p / m on n consecutive nodes of one body (records
// and velocities 8 per node; zero without mass). fix (null: applied later,
// after contact): fixed components; clear: zero the records with mass (and
// their gradient records when grad is not null) for the next p2g.
MPM_AVX_CLONES void remapNodes(double* r, double* v, std::size_t n, const std::uint8_t* fix, bool clear,
                               double* grad) {
  const double z = opaqueZero();
  const A4 zero = {z, z, z, z};
  for (std::size_t k = 0; k < n; ++k, r += 8, v += 8) {
    const double m = r[kM];
    if (!(m > 0)) {
      v[4] = v[5] = v[6] = 0.0;
      continue;
    }
    const A4 p = {r[kP], r[kP + 1], r[kP + 2], z};
    *reinterpret_cast<A4*>(v + 4) = p / A4{m, m, m, m};
    if (fix && fix[k])
      for (int c = 0; c < 3; ++c)
        if (fix[k] & (1 << c)) v[4 + c] = 0.0;
    if (clear) {
      *reinterpret_cast<A4*>(r) = zero;
      *reinterpret_cast<A4*>(r + 4) = zero;
      if (grad) {
        *reinterpret_cast<A4*>(grad + 8 * k) = zero;
        *reinterpret_cast<A4*>(grad + 8 * k + 4) = zero;
      }
    }
  }
}

}  // namespace

// Rigid r's contact (eqs 14-21) at node I (position xI, body masses mb) within
// the eq 22 gap: the impulse per body (summed by sumRigidForces in node order),
// the normal for the MUSL remap, the flags; returns whether it acted.
[[gnu::always_inline]] inline bool MpmSolver::rigidContactAt(std::size_t r, std::size_t I, const Vec3& xI,
                                                            const double* mb) {
  const std::size_t UB = static_cast<std::size_t>(cfg_.bodies);
  const RigidBody& rb = rigids_[r];
  Vec3 n;
  int part = 0;
  rb.distance(xI, &n, &part);
  if (part == 1) wallLipNormal(r, xI, n);  // a parting bevel: the wall-side lip meets the chisel (needle_cut.cpp)
  for (int c = 0; c < 3; ++c) rnormal_[3 * (r * nodes_ + I) + c] = n[c];
  std::uint8_t flag = 0;
  for (std::size_t b = 0; b < UB; ++b) {
    double* ib = &rimp_[3 * ((r * nodes_ + I) * UB + b)];
    std::fill_n(ib, 3, 0.0);
    if (!(mb[b] > 0)) continue;
    const Vec3 imp = rigidContact(mb[b], &vel_[8 * (b * nodes_ + I)], n, rb.velocity, rigidFriction(r, I));
    for (int c = 0; c < 3; ++c) ib[c] = imp[c];
    if (imp.squaredNorm() != 0.0) flag = 1;
  }
  active_[r * nodes_ + I] = static_cast<std::uint8_t>(flag | 2 | (part << 2));
  return flag != 0;
}

// Per (i, j) row and body: find the span of nodes with mass (reading the mass
// lanes only) and apply eq 3 there; then the node-wise contact and boundary
// conditions on the row's hull of spans. Outside the spans only what the last
// step's spans left is cleared: most nodes carry no mass, and their
// velocities (zero: the gathers read them at zero weight) and contact flags
// stay as they are. Threads take rows in equal shares of the work (a row's
// mass lanes plus its last-step spans). The arithmetic per node is the
// scalar one in four lanes (same operations, same roundings).
void MpmSolver::gridUpdate() {
  const std::size_t n1 = static_cast<std::size_t>(nn_[1]);
  const std::size_t rows = static_cast<std::size_t>(nn_[0]) * n1;
  const double start = wallSeconds(), cpuStart = cpuSeconds();
  planGridRows();
  clock_.add(PhaseClock::kGridPlan, start, cpuStart, wallSeconds(), cpuSeconds());
  // Node-wise work beyond eq 3 and the fixed components: rigid contact.
  const bool nodeWise = !rigids_.empty();
  std::size_t touchLo = rows, touchHi = 0;  // rows with rigid contact: [touchLo, touchHi)
  const double planned = wallSeconds(), cpuPlanned = cpuSeconds();
#pragma omp parallel num_threads(nthreads_) reduction(min : touchLo) reduction(max : touchHi)
  {
    const auto [qa, qb] = rowShare(rowWork_, threadId(), teamSize());
    for (std::size_t q = qa; q < qb; ++q) {
      const auto [h0, h1] = momentumUpdateRow(q, nodeWise);
      if (!nodeWise) continue;
      clearOutsideHull(q, h0, h1);
      if (contactOnRow(q, h0, h1)) {
        touchLo = std::min(touchLo, q);
        touchHi = std::max(touchHi, q + 1);
      }
    }
  }
  const double updated = wallSeconds(), cpuUpdated = cpuSeconds();
  sumRigidForces(touchLo, touchHi);
  clock_.add(PhaseClock::kGridUpdate, planned, cpuPlanned, updated, cpuUpdated);
  clock_.add(PhaseClock::kRigidSums, updated, cpuUpdated, wallSeconds(), cpuSeconds());
}

// gridUpdate: this step's spans become the last step's, and each row's work
// (its mass lanes plus its last-step spans) is summed for the threads' shares.
void MpmSolver::planGridRows() {
  const std::size_t R = rigids_.size();
  const std::size_t n1 = static_cast<std::size_t>(nn_[1]), n2 = static_cast<std::size_t>(nn_[2]);
  const std::size_t rows = static_cast<std::size_t>(nn_[0]) * n1, UB = static_cast<std::size_t>(cfg_.bodies);
  if (rowSpan_.size() != 2 * UB * rows) {  // first step: nothing set outside the (empty) spans
    rowSpan_.assign(2 * UB * rows, 0);
    rowSpanPrev_.assign(2 * UB * rows, 0);
    rowWork_.assign(rows + 1, 0);
  }
  if (rimp_.size() != 3 * UB * R * nodes_) rimp_.assign(3 * UB * R * nodes_, 0.0);
  rowSpan_.swap(rowSpanPrev_);
  for (std::size_t q = 0; q < rows; ++q) {
    std::uint64_t w = UB * n2;
    for (std::size_t b = 0; b < UB; ++b)
      w += 4 * (rowSpanPrev_[2 * (b * rows + q) + 1] - rowSpanPrev_[2 * (b * rows + q)]);
    rowWork_[q + 1] = rowWork_[q] + w;
  }
}

// gridUpdate on row q, per body: the span of the nodes with mass and eq 3 on
// it (the fixed components too unless nodeWise: contactOnRow applies them
// after the contact); the velocities the last step's span left outside it
// are cleared. Returns the hull [h0, h1) of the spans (h0 = n2, h1 = 0: none).
[[gnu::always_inline]] inline std::pair<std::size_t, std::size_t> MpmSolver::momentumUpdateRow(std::size_t q,
                                                                                              bool nodeWise) {
  const std::size_t NR = static_cast<std::size_t>(nr_), UB = static_cast<std::size_t>(cfg_.bodies);
  const std::size_t n1 = static_cast<std::size_t>(nn_[1]), n2 = static_cast<std::size_t>(nn_[2]);
  const std::size_t rows = static_cast<std::size_t>(nn_[0]) * n1;
  const double dt = dt_;
  const bool musl = cfg_.update == Update::MUSL;
  const double grav[3] = {cfg_.gravity.x(), cfg_.gravity.y(), cfg_.gravity.z()};
  double* rec = buf_[0].rec.data();
  double* vel = vel_.data();
  const double* dash = bounds_.dashpot.data();
  const std::uint8_t* fix = bounds_.fixMask.data();
  const std::size_t I0 = q * n2;
  std::size_t h0 = n2, h1 = 0;  // hull of this step's spans
  for (std::size_t b = 0; b < UB; ++b) {
    const std::size_t J0 = b * nodes_ + I0;
    const double* m = rec + NR * J0 + kM;
    std::size_t k0 = 0, k1 = n2;
    while (k0 < n2 && !(m[NR * k0] > 0)) ++k0;
    if (k0 == n2) k0 = k1 = 0;
    while (k1 > k0 && !(m[NR * (k1 - 1)] > 0)) --k1;
    std::uint32_t* span = &rowSpan_[2 * (b * rows + q)];
    const std::uint32_t* prev = &rowSpanPrev_[2 * (b * rows + q)];
    span[0] = static_cast<std::uint32_t>(k0);
    span[1] = static_cast<std::uint32_t>(k1);
    if (k1 > k0) {
      h0 = std::min(h0, k0);
      h1 = std::max(h1, k1);
    }
    // Outside the span: clear the velocities the last step's span left.
    for (std::size_t k = prev[0]; k < std::min<std::size_t>(prev[1], k0); ++k) std::fill_n(vel + 8 * (J0 + k), 8, 0.0);
    for (std::size_t k = std::max<std::size_t>(prev[0], k1); k < prev[1]; ++k) std::fill_n(vel + 8 * (J0 + k), 8, 0.0);
    if (k1 > k0)
      eq3Nodes(rec + NR * (J0 + k0), vel + 8 * (J0 + k0), dash + 3 * (I0 + k0), k1 - k0, dt, grav, musl,
               nodeWise ? nullptr : fix + I0 + k0);
  }
  return {h0, h1};
}

// gridUpdate on row q outside the hull [h0, h1) of its spans: clear the
// contact flags the last step left and reset the gap minima p2g wrote (its
// support reaches nodes of zero weight).
[[gnu::always_inline]] inline void MpmSolver::clearOutsideHull(std::size_t q, std::size_t h0, std::size_t h1) {
  const std::size_t R = rigids_.size(), UB = static_cast<std::size_t>(cfg_.bodies);
  const std::size_t n1 = static_cast<std::size_t>(nn_[1]), n2 = static_cast<std::size_t>(nn_[2]);
  const std::size_t rows = static_cast<std::size_t>(nn_[0]) * n1;
  const std::size_t I0 = q * n2;
  for (std::size_t b = 0; b < UB; ++b) {
    const std::uint32_t* prev = &rowSpanPrev_[2 * (b * rows + q)];
    for (std::size_t k = prev[0]; k < prev[1]; ++k)
      if (k < h0 || k >= h1)
        for (std::size_t r = 0; r < R; ++r) active_[r * nodes_ + I0 + k] = 0;
  }
  for (std::size_t r = 0; r < R; ++r) {
    double* gm = &buf_[0].gmin[r * nodes_ + I0];
    for (std::size_t k = 0; k < n2; ++k)
      if ((k < h0 || k >= h1) && gm[k] != kInf) gm[k] = kInf;  // reset for the next p2g
  }
}

// gridUpdate on the hull [h0, h1) of row q, node by node: the velocity
// contact of the two fields, the rigid contact where a point lies within the
// eq 22 gap, then the fixed velocity components; true when a rigid acted.
[[gnu::always_inline]] inline bool MpmSolver::contactOnRow(std::size_t q, std::size_t h0, std::size_t h1) {
  const int B = cfg_.bodies;
  const std::size_t R = rigids_.size(), UB = static_cast<std::size_t>(B);
  Buf& G = buf_[0];
  const double gap = rigidGap_;
  const std::size_t NR = static_cast<std::size_t>(nr_);
  const std::size_t n1 = static_cast<std::size_t>(nn_[1]), n2 = static_cast<std::size_t>(nn_[2]);
  const double* rec = G.rec.data();
  const std::uint8_t* fix = bounds_.fixMask.data();
  const std::size_t I0 = q * n2;
  const int i = static_cast<int>(q / n1), j = static_cast<int>(q % n1);
  bool touched = false;
  for (std::size_t k = h0; k < h1; ++k) {
    const std::size_t I = I0 + k;
    double mb[2] = {0, 0};
    bool any = false;
    for (std::size_t b = 0; b < UB; ++b) {
      mb[b] = rec[NR * (b * nodes_ + I) + kM];
      any = any || mb[b] > 0;
    }
    for (std::size_t r = 0; r < R; ++r) active_[r * nodes_ + I] = 0;
    if (!any) {
      for (std::size_t r = 0; r < R; ++r) G.gmin[r * nodes_ + I] = kInf;  // reset for the next p2g
      continue;
    }
    const Vec3 xI = cfg_.origin + cfg_.h * Vec3(i, j, static_cast<int>(k));
    for (std::size_t r = 0; r < R; ++r) {
      const double gm = G.gmin[r * nodes_ + I];
      G.gmin[r * nodes_ + I] = kInf;  // reset for the next p2g (gridUpdate is its only reader)
      if (!(gm < gap)) continue;  // eq 22: no particle touches the body here
      if (rigidContactAt(r, I, xI, mb)) touched = true;
    }
    const std::uint8_t mask = fix[I];
    if (mask)
      for (std::size_t b = 0; b < UB; ++b)
        for (int c = 0; c < 3; ++c)
          if (mask & (1 << c)) vel_[8 * (b * nodes_ + I) + c] = 0.0;
  }
  return touched;
}

// Force on each rigid body: the impulses in node order (the same sum on any
// number of threads); contact nodes lie in the spans of the rows [touchLo, touchHi).
void MpmSolver::sumRigidForces(std::size_t touchLo, std::size_t touchHi) {
  const std::size_t R = rigids_.size(), UB = static_cast<std::size_t>(cfg_.bodies);
  const std::size_t n2 = static_cast<std::size_t>(nn_[2]), rows = static_cast<std::size_t>(nn_[0]) * nn_[1];
  const double dt = dt_;
  for (std::size_t r = 0; r < R; ++r) {
    std::array<double, 9> a{};  // total(3) shaft(3) tip(3)
    int count = 0;
    for (std::size_t q = touchLo; q < touchHi; ++q) {
      std::size_t h0 = n2, h1 = 0;
      for (std::size_t b = 0; b < UB; ++b) {
        const std::uint32_t* span = &rowSpan_[2 * (b * rows + q)];
        if (span[1] > span[0]) {
          h0 = std::min<std::size_t>(h0, span[0]);
          h1 = std::max<std::size_t>(h1, span[1]);
        }
      }
      for (std::size_t k = h0; k < h1; ++k) {
        const std::size_t I = q * n2 + k;
        const std::uint8_t flag = active_[r * nodes_ + I];
        if (!(flag & 1)) continue;
        ++count;
        const int part = flag >> 2;
        for (std::size_t b = 0; b < UB; ++b) {
          const double* ib = &rimp_[3 * ((r * nodes_ + I) * UB + b)];
          const Vec3 imp(ib[0], ib[1], ib[2]);
          if (imp.squaredNorm() == 0.0) continue;
          for (int c = 0; c < 3; ++c) {
            a[static_cast<std::size_t>(c)] -= imp[c] / dt;                   // force on the rigid body
            a[static_cast<std::size_t>(3 * (part + 1) + c)] -= imp[c] / dt;  // shaft (part 0 -> 3..5) or tip (part 1 -> 6..8)
          }
        }
      }
    }
    RigidForce f;
    f.total += Vec3(a[0], a[1], a[2]);
    f.tip += Vec3(a[6], a[7], a[8]);    // part 1
    f.shaft += Vec3(a[3], a[4], a[5]);  // part 0
    f.contactNodes = count;
    rforce_[r] = f;
  }
}

// The node's material (gmat) is the one p2g recorded this step: read only at
// nodes whose gap minimum it lowered (gridUpdate, remapUpdate of that step).
double MpmSolver::rigidFriction(std::size_t r, std::size_t I) const {
  if (materialFriction_.empty()) return rigids_[r].friction;
  const double mu = materialFriction_[buf_[0].gmat[r * nodes_ + I]];
  return mu >= 0.0 ? mu : rigids_[r].friction;
}

// After the momentum remap of MUSL: the same contact (at the nodes found in
// the first update, with their normals) and boundary conditions on v*. Only
// the spans gridUpdate found: outside them the records and velocities are
// zero and no contact flag is set.
void MpmSolver::remapUpdate(bool clear) {
  const int B = cfg_.bodies;
  const std::size_t R = rigids_.size();
  Buf& G = buf_[0];
  const std::size_t NR = static_cast<std::size_t>(nr_);
  const std::size_t n1 = static_cast<std::size_t>(nn_[1]), n2 = static_cast<std::size_t>(nn_[2]);
  const std::size_t rows = static_cast<std::size_t>(nn_[0]) * n1, UB = static_cast<std::size_t>(B);
  for (std::size_t q = 0; q < rows; ++q) {
    std::uint64_t w = 1;
    for (std::size_t b = 0; b < UB; ++b) w += rowSpan_[2 * (b * rows + q) + 1] - rowSpan_[2 * (b * rows + q)];
    rowWork_[q + 1] = rowWork_[q] + w;
  }
  const bool nodeWise = R > 0;
  double* rec = G.rec.data();
  double* vel = vel_.data();
  const std::uint8_t* fix = bounds_.fixMask.data();
#pragma omp parallel num_threads(nthreads_)
  {
    const auto [qa, qb] = rowShare(rowWork_, threadId(), teamSize());
    for (std::size_t q = qa; q < qb; ++q) {
      const std::size_t I0 = q * n2;
      std::size_t h0 = n2, h1 = 0;  // hull of the spans
      for (std::size_t b = 0; b < UB; ++b) {
        const std::size_t J0 = b * nodes_ + I0;
        const std::size_t k0 = rowSpan_[2 * (b * rows + q)], k1 = rowSpan_[2 * (b * rows + q) + 1];
        if (k1 > k0) {
          h0 = std::min(h0, k0);
          h1 = std::max(h1, k1);
        }
        if (k1 > k0)  // contact first (node-wise below): the fixed components and the clearing after it
          remapNodes(rec + NR * (J0 + k0), vel + 8 * (J0 + k0), k1 - k0, nodeWise ? nullptr : fix + I0 + k0,
                     clear && !nodeWise, B > 1 ? &G.grad[8 * (J0 + k0)] : nullptr);
      }
      if (!nodeWise) continue;
      for (std::size_t k = h0; k < h1; ++k) {
        const std::size_t I = I0 + k;
        double mb[2] = {0, 0};
        for (std::size_t b = 0; b < UB; ++b) mb[b] = rec[NR * (b * nodes_ + I) + kM];
        for (std::size_t r = 0; r < R; ++r) {
          if (!(active_[r * nodes_ + I] & 2)) continue;
          const double* nn = &rnormal_[3 * (r * nodes_ + I)];
          const Vec3 n(nn[0], nn[1], nn[2]);
          for (std::size_t b = 0; b < UB; ++b)
            if (mb[b] > 0) rigidContact(mb[b], &vel_[8 * (b * nodes_ + I) + 4], n, rigids_[r].velocity, rigidFriction(r, I));
        }
        const std::uint8_t mask = fix[I];
        if (mask)
          for (std::size_t b = 0; b < UB; ++b)
            for (int c = 0; c < 3; ++c)
              if (mask & (1 << c)) vel_[8 * (b * nodes_ + I) + 4 + c] = 0.0;
        // Last use of the records this step: clear them for the next p2g while
        // they are in cache (a record without mass holds only zeros already).
        if (clear)
          for (std::size_t b = 0; b < UB; ++b)
            if (mb[b] > 0) {
              std::fill_n(&G.rec[NR * (b * nodes_ + I)], 8, 0.0);  // NR = 8 (one line, as p2g)
              if (B > 1) std::fill_n(&G.grad[8 * (b * nodes_ + I)], 8, 0.0);
            }
      }
    }
  }
  if (clear) gridClean_ = true;
}

}  // namespace needlesim::mpm
