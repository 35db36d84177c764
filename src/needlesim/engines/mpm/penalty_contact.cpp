// Penalty contact of two deformable bodies between material points (seed 000
// eqs 14-21 with the normal impulse of eqs 15-18 replaced by a pair penalty;
// penalty_contact.hpp, docs/models/mpm.md "Penalty contact of two bodies").
#include "needlesim/engines/mpm/penalty_contact.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "needlesim/contact/coulomb.hpp"
#include "needlesim/contact/penalty.hpp"
#include "needlesim/engines/mpm/grid_kernels.hpp"
#include "needlesim/engines/mpm/mpm_solver.hpp"

#ifdef _OPENMP
#include <omp.h>
#endif

namespace needlesim::mpm {

namespace {
using grid::kF;  // force lanes of a grid record (grid_kernels.hpp)
// f_I += N_Ip f (force lanes) at the nodes of a point at x in the records of
// its body (off = body * nodes), S = 3 (B-spline) or 2 (linear).
template <int S>
inline void scatterForce(const double* x, const double* o, double invh, const double* f, double* rec, std::size_t NR,
                         std::size_t off, std::size_t n1, std::size_t n2) {
  const auto st = grid::stencil<S>(x, o[0], o[1], o[2], invh);
  for (int i = 0; i < S; ++i)
    for (int j = 0; j < S; ++j) {
      const double wij = st.wx[i] * st.wy[j];
      const double fa[3] = {wij * f[0], wij * f[1], wij * f[2]};
      double* r = rec +
                  NR * (off + (static_cast<std::size_t>(st.bx + i) * n1 + static_cast<std::size_t>(st.by + j)) * n2 +
                        static_cast<std::size_t>(st.bz)) +
                  kF;
      for (int k = 0; k < S; ++k, r += NR)
        for (int c = 0; c < 3; ++c) r[c] += st.wz[k] * fa[c];
    }
}
// sum_I N_I p_I / m_I over the nodes with mass of a point at x, records of
// its body (off = body * nodes); per (i, j) the k sum first (tensor product).
template <int S>
inline void gatherVelocity(const double* x, const double* o, double invh, const double* rec, std::size_t NR,
                           std::size_t off, std::size_t n1, std::size_t n2, double* v) {
  const auto st = grid::stencil<S>(x, o[0], o[1], o[2], invh);
  double v0 = 0.0, v1 = 0.0, v2 = 0.0;
  for (int i = 0; i < S; ++i)
    for (int j = 0; j < S; ++j) {
      const double* r = rec + NR * (off + (static_cast<std::size_t>(st.bx + i) * n1 + static_cast<std::size_t>(st.by + j)) * n2 +
                                    static_cast<std::size_t>(st.bz));
      double s0 = 0.0, s1 = 0.0, s2 = 0.0;
      for (int k = 0; k < S; ++k, r += NR) {
        if (!(r[0] > 0.0)) continue;
        const double wk = st.wz[k] / r[0];
        s0 += wk * r[1];
        s1 += wk * r[2];
        s2 += wk * r[3];
      }
      const double wij = st.wx[i] * st.wy[j];
      v0 += wij * s0;
      v1 += wij * s1;
      v2 += wij * s2;
    }
  v[0] = v0;
  v[1] = v1;
  v[2] = v2;
}
}  // namespace

double PairPenalty::limit(const PenaltyTally& t, double alpha) const {
  if (!(alpha > 0.0) || t.pairs + t.close == 0 || !(mr_ > 0.0) || !(k_ > 0.0))
    return std::numeric_limits<double>::infinity();
  return std::min(alpha / std::sqrt(std::max(k_, t.tangent) / mr_), alpha * t.travel);
}

PairPenalty::PairPenalty(double stiffness, std::vector<double> radius, double reducedMass, int threads)
    : k_(stiffness),
      radius_(std::move(radius)),
      mr_(reducedMass),
      thread_(static_cast<std::size_t>(std::max(threads, 1))),
      pairs_(thread_.size()),
      friction_(8 * thread_.size(), 0.0) {
  for (double r : radius_) rmax_ = std::max(rmax_, r);
}

// Coulomb friction on a pair in contact (eqs 19-21), added to f (the force
// on p); returns the pair's friction work over the step (J). The normal
// is that of the bodies' surfaces, from the two mass gradients interpolated
// at the pair's midpoint (eqs 14-21), not the pair axis n:
// on two lattices sliding past each other the pair axis tilts by up to
// 30 deg and the friction along it fell to half of mu times the normal
// impulse. Sticking force m_r |v_t| / dt of the pair (eq 19), limited by mu
// times the pair force's component along that normal (eqs 20-21).
double MpmSolver::pairFriction(std::size_t p, std::size_t q, const double* n, double fn, double mu, double dt,
                               const double* vp, const double* vq, double* f) const {
  // Mass gradients of both bodies interpolated (trilinear) at the pair's
  // midpoint (surfaceNormal): a single node beside the interface would see the
  // two bodies at different depths, and the normal would tilt at the edges of the face.
  const double mid[3] = {0.5 * (P_[p].x[0] + P_[q].x[0]), 0.5 * (P_[p].x[1] + P_[q].x[1]),
                         0.5 * (P_[p].x[2] + P_[q].x[2])};
  double m[3];
  if (!surfaceNormal(mid, m)) return 0.0;
  if (body_[p] == 0)  // oriented from q's body to p's (as n)
    for (double& c : m) c = -c;
  const double fN = fn * (n[0] * m[0] + n[1] * m[1] + n[2] * m[2]);
  if (!(fN > 0.0)) return 0.0;
  // Sliding velocity from each point's own body field on the grid, sum N v_I
  // at the point (the particle velocities carry the FLIP noise of the impact
  // in all directions; a field read at a node off the interface sees the
  // other depth's lateral expansion): vp, vq from fieldVelocity.
  const double mr = P_[p].mass * P_[q].mass / (P_[p].mass + P_[q].mass);
  return contact::coulombPair(m, fN, vp, vq, mr, mu, dt, f);
}

// The bodies' surface normal at x, from the two mass gradients interpolated
// (trilinear) there: m = g0 / |g0| - g1 / |g1|, normalised (out of body 0,
// into body 1); false where a body has no gradient.
bool MpmSolver::surfaceNormal(const double* x, double* m) const {
  const double invh = 1.0 / cfg_.h;
  const std::size_t n1 = static_cast<std::size_t>(nn_[1]), n2 = static_cast<std::size_t>(nn_[2]);
  const double* grad = buf_[0].grad.data();
  const double xm[3] = {(x[0] - cfg_.origin.x()) * invh, (x[1] - cfg_.origin.y()) * invh, (x[2] - cfg_.origin.z()) * invh};
  int b[3];
  double t[3];
  for (int d = 0; d < 3; ++d) {
    b[d] = static_cast<int>(xm[d]);
    t[d] = xm[d] - b[d];
  }
  double g0[3] = {0, 0, 0}, g1[3] = {0, 0, 0};
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 2; ++j)
      for (int k = 0; k < 2; ++k) {
        const double w = (i ? t[0] : 1 - t[0]) * (j ? t[1] : 1 - t[1]) * (k ? t[2] : 1 - t[2]);
        const std::size_t I = (static_cast<std::size_t>(b[0] + i) * n1 + static_cast<std::size_t>(b[1] + j)) * n2 +
                              static_cast<std::size_t>(b[2] + k);
        for (int c = 0; c < 3; ++c) {
          g0[c] += w * grad[8 * I + grid::kG + c];
          g1[c] += w * grad[8 * (nodes_ + I) + grid::kG + c];
        }
      }
  const double a0 = std::sqrt(g0[0] * g0[0] + g0[1] * g0[1] + g0[2] * g0[2]);
  const double a1 = std::sqrt(g1[0] * g1[0] + g1[1] * g1[1] + g1[2] * g1[2]);
  if (!(a0 > 0) || !(a1 > 0)) return false;
  for (int c = 0; c < 3; ++c) m[c] = g0[c] / a0 - g1[c] / a1;
  const double mm = std::sqrt(m[0] * m[0] + m[1] * m[1] + m[2] * m[2]);
  if (!(mm > 0)) return false;
  const double s = 1.0 / mm;  // multiply by the reciprocal: the pair friction is written with this rounding
  for (int c = 0; c < 3; ++c) m[c] *= s;
  return true;
}

// Velocity of a point's own body field before the update, sum_I N_Ip p_I / m_I.
void MpmSolver::fieldVelocity(std::size_t p, const double* rec, std::size_t NR, double* v) const {
  const double invh = 1.0 / cfg_.h;
  const std::size_t n1 = static_cast<std::size_t>(nn_[1]), n2 = static_cast<std::size_t>(nn_[2]);
  const std::size_t off = static_cast<std::size_t>(body_[p]) * nodes_;
  const double* o = cfg_.origin.data();
  if (cfg_.shape != Shape::Linear)
    gatherVelocity<3>(P_[p].x, o, invh, rec, NR, off, n1, n2, v);
  else
    gatherVelocity<2>(P_[p].x, o, invh, rec, NR, off, n1, n2, v);
}

void PairPenalty::bin(const std::uint32_t* nearCell, const std::uint8_t* body, std::size_t n, std::size_t nodes) {
  cand_.clear();
  candKey_.clear();
  cells0_.clear();
  cells1_.clear();
  start_.assign(2 * nodes + 1, 0);
  for (std::size_t p = 0; p < n; ++p) {
    // the other body in the cells around the point's cell (NearBodies::mark; p2g set the cell)
    if (nearCell[p] == ~std::uint32_t{0}) continue;
    const std::size_t c = nearCell[p];
    const std::size_t key = static_cast<std::size_t>(body[p]) * nodes + c;
    cand_.push_back(static_cast<std::uint32_t>(p));
    candKey_.push_back(static_cast<std::uint32_t>(key));
    if (start_[key + 1]++ == 0) (key < nodes ? cells0_ : cells1_).push_back(static_cast<std::uint32_t>(c));
  }
  for (std::size_t c = 0; c < 2 * nodes; ++c) start_[c + 1] += start_[c];
  const std::size_t nc = cand_.size();
  items_.resize(nc);
  cursor_.assign(start_.begin(), start_.end() - 1);
  for (std::size_t a = 0; a < nc; ++a) items_[cursor_[candKey_[a]]++] = cand_[a];
  first1_ = start_[nodes];
  box_.resize(6 * nodes);
}

// Bounding box of the points of each body-1 cell with candidates (inside a
// parallel region: the cells are shared out by an orphaned omp for).
void PairPenalty::cellBoxes(const double* x, std::size_t stride, std::size_t nodes) {
  const std::size_t ncell1 = cells1_.size();
#pragma omp for schedule(static)
  for (std::size_t ic = 0; ic < ncell1; ++ic) {
    const std::size_t c = cells1_[ic];
    double* bx = box_.data() + 6 * c;
    for (int d = 0; d < 3; ++d) {
      bx[d] = std::numeric_limits<double>::infinity();
      bx[3 + d] = -std::numeric_limits<double>::infinity();
    }
    for (std::uint32_t s = start_[nodes + c]; s < start_[nodes + c + 1]; ++s)
      for (int d = 0; d < 3; ++d) {
        const double v = x[stride * items_[s] + static_cast<std::size_t>(d)];
        bx[d] = std::min(bx[d], v);
        bx[3 + d] = std::max(bx[3 + d], v);
      }
  }
}

int PairPenalty::nearCells(std::size_t c0, int reach, std::size_t nodes, std::size_t n1, std::size_t n2,
                           const long long* lim, std::uint32_t* lo, std::uint32_t* hi, const double** bb) const {
  const long long ci[3] = {static_cast<long long>(c0 / (n1 * n2)), static_cast<long long>((c0 / n2) % n1),
                           static_cast<long long>(c0 % n2)};
  const long long R = reach;
  int nb = 0;
  for (long long i = std::max(0LL, ci[0] - R); i <= std::min(lim[0] - 1, ci[0] + R); ++i)
    for (long long j = std::max(0LL, ci[1] - R); j <= std::min(lim[1] - 1, ci[1] + R); ++j)
      for (long long kk = std::max(0LL, ci[2] - R); kk <= std::min(lim[2] - 1, ci[2] + R); ++kk) {
        const std::size_t c = nodes + (static_cast<std::size_t>(i) * n1 + static_cast<std::size_t>(j)) * n2 +
                              static_cast<std::size_t>(kk);
        if (start_[c] == start_[c + 1]) continue;
        lo[nb] = start_[c];
        hi[nb] = start_[c + 1];
        bb[nb] = box_.data() + 6 * (c - nodes);
        ++nb;
      }
  return nb;
}

// Totals of the threads' tallies (sums, largest, smallest; the same order on every thread).
PenaltyTally PairPenalty::sum() const {
  PenaltyTally all;
  for (const PenaltyTally& t : thread_) {
    all.energy += t.energy;
    all.penetration = std::max(all.penetration, t.penetration);
    all.tangent = std::max(all.tangent, t.tangent);
    all.travel = std::min(all.travel, t.travel);
    all.pairs += t.pairs;
    all.close += t.close;
  }
  return all;
}

// Scatter f_I += N_Ip f_p of the slots' contact forces (force_; body-1
// reactions of threads t > 0 in reaction_[t]) into each point's own body (a
// thin shell), inside the parallel region after the forces' barrier: the
// body-0 slots [0, first1) touch only body 0's records, the body-1 slots only
// body 1's, so the last thread scatters body 1 (after adding the other
// threads' reactions to its slots) while thread 0 scatters body 0.
void MpmSolver::scatterContact(std::size_t tid) {
  PairPenalty& P = *penalty_;
  const double invh = 1.0 / cfg_.h;
  const std::size_t n1 = static_cast<std::size_t>(nn_[1]), n2 = static_cast<std::size_t>(nn_[2]);
  const std::size_t NR = static_cast<std::size_t>(nr_);
  const std::size_t nc = P.cand_.size(), first1 = P.first1_, nthreads = P.thread_.size();
  const bool bspline = cfg_.shape != Shape::Linear;
  double* rec = buf_[0].rec.data();
  const double* o = cfg_.origin.data();
#ifdef _OPENMP
  const std::size_t team = static_cast<std::size_t>(omp_get_num_threads());
#else
  const std::size_t team = 1;
#endif
  for (int body = 0; body < 2; ++body) {
    if (tid != (body == 0 ? 0 : team - 1)) continue;
    const std::size_t s0 = body == 0 ? 0 : first1, s1 = body == 0 ? first1 : nc;
    if (body == 1)
      for (std::size_t t = 1; t < nthreads; ++t)
        if (!P.reaction_[t].empty())
          for (std::size_t s = 3 * first1; s < 3 * nc; ++s) P.force_[s] += P.reaction_[t][s - 3 * first1];
    const std::size_t off = static_cast<std::size_t>(body) * nodes_;
    for (std::size_t a = s0; a < s1; ++a) {
      const double* f = &P.force_[3 * a];
      if (f[0] == 0.0 && f[1] == 0.0 && f[2] == 0.0) continue;
      const std::size_t p = P.items_[a];
      if (bspline)
        scatterForce<3>(P_[p].x, o, invh, f, rec, NR, off, n1, n2);
      else
        scatterForce<2>(P_[p].x, o, invh, f, rec, NR, off, n1, n2);
    }
  }
}

double PairPenalty::frictionWork() const {
  double w = 0.0;
  for (std::size_t t = 0; t < friction_.size(); t += 8) w += friction_[t];
  return w;
}

void PairPenalty::resetFriction() { std::fill(friction_.begin(), friction_.end(), 0.0); }

// The pair law (penalty_contact.hpp, contact/penalty.hpp).
double PairPenalty::pairForce(double delta, double d) const { return contact::pairPenaltyForce(k_, delta, d); }
double PairPenalty::pairTangent(double delta, double d) const { return contact::pairPenaltyTangent(k_, delta, d); }
double PairPenalty::pairEnergy(double delta, double d) const { return contact::pairPenaltyEnergy(k_, delta, d); }

// Stored energy at the positions after the step (the strain energy of the
// report is also that of the step's end) over the pairs in contact at its
// start; a pair that came into contact during the step holds O((v dt)^2).
void MpmSolver::penaltyEnergyAfterStep() {
  PairPenalty& P = *penalty_;
  double e = 0.0, kt = 0.0;
  for (const auto& list : P.pairs_)
    for (const auto& pq : list) {
      const std::size_t p = pq[0], q = pq[1];
      const double d = P.radius_[p] + P.radius_[q];
      const double dx = P_[p].x[0] - P_[q].x[0], dy = P_[p].x[1] - P_[q].x[1], dz = P_[p].x[2] - P_[q].x[2];
      const double delta = d - std::sqrt(dx * dx + dy * dy + dz * dz);
      if (delta > 0.0 && delta < d) {
        e += P.pairEnergy(delta, d);
        kt = std::max(kt, P.pairTangent(delta, d));
      }
    }
  P.tally_.energy = e;
  // The next step starts here: its limit follows the stiffer of the two ends.
  P.tally_.tangent = std::max(P.tally_.tangent, kt);
}

// Pair forces at the positions of the step's start, added to the reduced grid
// force f_I of each point's own body before the momentum update (eq 3), so
// the grid update, MUSL remap and boundary conditions treat them like the
// internal force. Candidates are the points in cells that both bodies reach
// within 3 cells (NearBodies::mark); d_p <= h, so a partner lies in the 27
// cells around a point's cell. Each pair is visited once, from the cell of
// its body-0 point: the pair force acts on p and its opposite on q (the
// normal force, the friction force and the pair's friction work are odd in
// the exchange p <-> q to the last bit, pairFriction), so the forces equal
// those of a search from both sides up to the order of the sums.
void MpmSolver::penaltyForces() {
  PairPenalty& P = *penalty_;
  // Cell lists of the candidates (counting sort, serial), per body and cell
  // (key body * nodes + cell), so a point scans only the other body's points.
  P.bin(nearCell_.data(), body_.data(), size(), nodes_);
  const std::size_t nc = P.cand_.size();  // body-1 items follow all body-0 items: slots [first1_, nc)
  const std::size_t nthreads = P.thread_.size();
  P.force_.assign(3 * nc, 0.0);
  P.reaction_.resize(nthreads);
  for (auto& t : P.thread_) t = PenaltyTally{};
  P.resetFriction();
  P.contacts_.resize(nthreads);
  P.vfield_.resize(3 * nc);
  P.need_.assign(nc, 0);
  const std::uint8_t* need = P.need_.data();
  const double dt0 = dt_, mu = cfg_.friction;
  const std::size_t NR = static_cast<std::size_t>(nr_);
  const double* rec0 = buf_[0].rec.data();
  const std::size_t ncell = P.cells0_.size();
  for (auto& r : P.reaction_) r.clear();  // a thread that does not run this step adds nothing
#pragma omp parallel num_threads(nthreads_)
  {
#ifdef _OPENMP
    const std::size_t tid = static_cast<std::size_t>(omp_get_thread_num());
#else
    const std::size_t tid = 0;
#endif
    P.pairs_[tid].clear();
    P.contacts_[tid].clear();
    // Bounding boxes of the body-1 cells: a body-0 point skips a cell farther
    // than 1.5 (r_p + r_max) along an axis (no pair there passes the distance test).
    P.cellBoxes(P_[0].x, sizeof(Point) / sizeof(double), nodes_);
#pragma omp for schedule(static)
    for (std::size_t ic = 0; ic < ncell; ++ic) penaltyPairsOfCell(P.cells0_[ic], tid, dt0, mu);
    // The step's own limit (after the barrier of the search): the pairs'
    // tangent stiffness and approach at its start (PairPenalty::limit), the
    // same reduction on every thread (no single and its barrier).
    const PenaltyTally all = P.sum();
    const double dt = cfg_.fixedTimeStep > 0 ? dt0 : std::min(dt0, P.limit(all, cfg_.penaltyStepFactor));
    // Field velocity of each point in a pair, once (after the barrier of the
    // search); chunks spread the pairs' slots (the face cells) over the threads.
    if (mu > 0.0) {
#pragma omp for schedule(static, 16)
      for (std::size_t s = 0; s < nc; ++s)
        if (need[s]) fieldVelocity(P.items_[s], rec0, NR, &P.vfield_[3 * s]);
    }
    penaltyPairForces(tid, mu, dt);
#pragma omp barrier
    scatterContact(tid);
    if (tid == 0) dt_ = dt;
  }
  P.tally_ = P.sum();
}

// penaltyForces, the search from the body-0 cell c0 on thread tid: the
// pairs in contact (into the thread's tally, pairs and contacts; with
// friction their slots marked in need_) and those close to it.
[[gnu::always_inline]] inline void MpmSolver::penaltyPairsOfCell(std::size_t c0, std::size_t tid, double dt0,
                                                                 double mu) {
  PairPenalty& P = *penalty_;
  const std::size_t n1 = static_cast<std::size_t>(nn_[1]), n2 = static_cast<std::size_t>(nn_[2]);
  const long long lim[3] = {nn_[0], nn_[1], nn_[2]};
  std::uint8_t* need = P.need_.data();
  PenaltyTally& T = P.thread_[tid];
  auto& Pairs = P.pairs_[tid];
  auto& Contacts = P.contacts_[tid];
  // The occupied body-1 cells among the 27 around c0 (slot ranges).
  std::uint32_t lo[27], hi[27];
  const double* bb[27];
  const int nb = P.nearCells(c0, 1, nodes_, n1, n2, lim, lo, hi, bb);
  if (nb == 0) return;
  for (std::uint32_t sp = P.start_[c0]; sp < P.start_[c0 + 1]; ++sp) {
    const std::size_t p = P.items_[sp];
    const double reach = 1.5 * (P.radius_[p] + P.rmax_) * (1 + 1e-12);
    const double* xp = P_[p].x;
    for (int b = 0; b < nb; ++b) {
      const double* bx = bb[b];
      if (xp[0] < bx[0] - reach || xp[0] > bx[3] + reach || xp[1] < bx[1] - reach || xp[1] > bx[4] + reach ||
          xp[2] < bx[2] - reach || xp[2] > bx[5] + reach)
        continue;
      for (std::uint32_t sq = lo[b]; sq < hi[b]; ++sq) {
        const std::size_t q = P.items_[sq];
        const double dx = P_[p].x[0] - P_[q].x[0], dy = P_[p].x[1] - P_[q].x[1], dz = P_[p].x[2] - P_[q].x[2];
        const double r2 = dx * dx + dy * dy + dz * dz;
        const double d = P.radius_[p] + P.radius_[q];  // contact distance of the two points' volumes
        if (!(r2 < 2.25 * d * d) || !(r2 > 0.0)) continue;
        const double r = std::sqrt(r2), delta = d - r;
        const double n[3] = {dx / r, dy / r, dz / r};  // from q to p
        // approach speed of the pair (> 0: closing)
        const double vn = (P_[q].v[0] - P_[p].v[0]) * n[0] + (P_[q].v[1] - P_[p].v[1]) * n[1] + (P_[q].v[2] - P_[p].v[2]) * n[2];
        if (!(delta > 0.0)) {
          // Not touching: close if it would within two steps at the
          // current approach speed (the next step resolves the contact).
          if (-delta < 2.0 * vn * dt0) {
            T.close += 1;
            T.travel = std::min(T.travel, r / vn);
          }
          continue;
        }
        if (vn > 0.0) T.travel = std::min(T.travel, r / vn);
        T.energy += P.pairEnergy(delta, d);
        T.penetration = std::max(T.penetration, delta);
        T.tangent = std::max(T.tangent, P.pairTangent(delta, d));
        T.pairs += 1;
        Pairs.push_back({static_cast<std::uint32_t>(p), static_cast<std::uint32_t>(q)});
        Contacts.push_back({sp, sq, {n[0], n[1], n[2]}, P.pairForce(delta, d)});
        if (mu > 0.0) {  // several threads may mark q: atomic stores of the same value
          __atomic_store_n(need + sp, std::uint8_t{1}, __ATOMIC_RELAXED);
          __atomic_store_n(need + sq, std::uint8_t{1}, __ATOMIC_RELAXED);
        }
      }
    }
  }
}

// penaltyForces, the pair forces of thread tid's contacts: fp (with the
// friction at step dt) on p (this thread's cells), -fp on q. Reactions on
// body-1 slots: thread 0 into force_, the others into their own buffer.
void MpmSolver::penaltyPairForces(std::size_t tid, double mu, double dt) {
  PairPenalty& P = *penalty_;
  double& W = P.friction_[8 * tid];
  // slot s at react[3 (s - reactFrom)]
  const auto [react, reactFrom] = reactionSink(P.force_.data(), P.reaction_[tid], 3, tid, P.first1_, P.cand_.size());
  for (const PairPenalty::Contact& C : P.contacts_[tid]) {
    const std::size_t p = P.items_[C.sp], q = P.items_[C.sq];
    double fp[3] = {C.fn * C.n[0], C.fn * C.n[1], C.fn * C.n[2]};
    if (mu > 0.0) W += pairFriction(p, q, C.n, C.fn, mu, dt, &P.vfield_[3 * C.sp], &P.vfield_[3 * C.sq], fp);
    for (int c3 = 0; c3 < 3; ++c3) {
      P.force_[3 * C.sp + c3] += fp[c3];
      react[3 * (C.sq - reactFrom) + c3] -= fp[c3];
    }
  }
}

// Tests: the pair contact forces without friction at the current
// positions (every point a candidate, so the search misses no pair), and the
// stored energy there. The grid records it scattered into are cleared by the
// next p2g; the friction coefficient, step and tally are restored.
double MpmSolver::contactForces(std::vector<Vec3>& force) {
  if (!finalized_) finalize();
  force.assign(size(), Vec3::Zero());
  if (!penalty_) return 0.0;
  const double invh = 1.0 / cfg_.h;
  const std::size_t n1 = static_cast<std::size_t>(nn_[1]), n2 = static_cast<std::size_t>(nn_[2]);
  nearCell_.resize(size());
  for (std::size_t p = 0; p < size(); ++p) {
    const grid::Cell c = grid::cellAt((P_[p].x[0] - cfg_.origin.x()) * invh, (P_[p].x[1] - cfg_.origin.y()) * invh,
                                      (P_[p].x[2] - cfg_.origin.z()) * invh, n1);
    nearCell_[p] = static_cast<std::uint32_t>(c.row * n2 + c.k);
  }
  const double mu = cfg_.friction, dt = dt_ > 0.0 ? dt_ : stableTimeStep();
  const PenaltyTally tally = penalty_->tally_;
  cfg_.friction = 0.0;
  dt_ = dt;
  penaltyForces();
  gridClean_ = false;
  PairPenalty& P = *penalty_;
  for (std::size_t s = 0; s < P.cand_.size(); ++s)
    force[P.items_[s]] += Vec3(P.force_[3 * s], P.force_[3 * s + 1], P.force_[3 * s + 2]);
  const double e = P.tally_.energy;
  cfg_.friction = mu;
  dt_ = dt;
  P.tally_ = tally;
  return e;
}

}  // namespace needlesim::mpm
