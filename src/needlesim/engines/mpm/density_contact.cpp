// Density contact of two deformable bodies (seed 000 eqs 14-21 with the
// normal impulse of eqs 15-18 replaced by a many-body penalty on the smoothed
// volume fractions of the bodies; density_contact.hpp, docs/models/mpm.md
// "Density contact of two bodies"). The search, reactions and scatter are the
// pair penalty's (penalty_contact.cpp).
#include "needlesim/engines/mpm/density_contact.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <numbers>

#include "needlesim/contact/coulomb.hpp"
#include "needlesim/core/error.hpp"
#include "needlesim/engines/mpm/grid_kernels.hpp"
#include "needlesim/engines/mpm/mpm_solver.hpp"

#ifdef _OPENMP
#include <omp.h>
#endif

namespace needlesim::mpm {

namespace {
constexpr double kSupport = 3.0;  // kernel support H in point spacings
constexpr double kInf = std::numeric_limits<double>::infinity();
}  // namespace

WendlandC2::WendlandC2(double support) : H(support), c(21.0 / (2.0 * std::numbers::pi * support * support * support)) {}

double WendlandC2::value(double r) const {
  const double q = r / H;
  if (!(q < 1.0)) return 0.0;
  const double u = 1.0 - q, u2 = u * u;
  return c * u2 * u2 * (1.0 + 4.0 * q);
}

double WendlandC2::slopeOverR(double r) const {
  const double q = r / H;
  if (!(q < 1.0)) return 0.0;
  const double u = 1.0 - q;
  return 20.0 * c / (H * H) * u * u * u;
}

double WendlandC2::hessianBound(double r) const {
  const double q = r / H;
  if (!(q < 1.0)) return 0.0;
  const double u = 1.0 - q;
  return 20.0 * c / (H * H) * u * u * std::max(std::abs(1.0 - 4.0 * q), u);
}

LatticeFraction latticeFraction(const WendlandC2& W, double s, double t) {
  const int n = static_cast<int>(std::ceil(W.H / s)) + 1;
  LatticeFraction f;
  const double V = s * s * s;
  for (int i = -n; i <= n; ++i)
    for (int j = -n; j <= n; ++j)
      for (int k = 0; k <= n; ++k) {
        const double z = t + k * s;
        const double r = std::sqrt((i * s) * (i * s) + (j * s) * (j * s) + z * z);
        f.phi += V * W.value(r);
        f.slope += V * W.slopeOverR(r) * z;  // -d phi / dz = sum V (-W'(r) / r) (z - z_p)
      }
  return f;
}

DensityLaw makeDensityLaw(const std::vector<double>& radius, const std::vector<std::uint8_t>& body, double dp, double h) {
  DensityLaw D;
  for (std::size_t p = 0; p < radius.size(); ++p) D.spacing[body[p]] = std::max(D.spacing[body[p]], 2.0 * radius[p]);
  // Support 3 x the larger spacing (docs/models/mpm.md): the frictionless
  // oblique sphere impact spins the spheres by omega R / v0 = 0.29 at 2
  // spacings, 0.09 at 2.5, 0.016 at 3 (the terraces of a lattice surface
  // inclined to the lattice axes are longer than one spacing).
  const double H = kSupport * std::max(D.spacing[0], D.spacing[1]);
  D.kernel = WendlandC2(H);
  D.reach = static_cast<int>(std::ceil(H / h * (1 - 1e-9)));
  if (D.reach > 3)
    throw Error(fmt::format("mpm: the density contact needs particle spacings of at most the grid spacing ({:.3g} mm > "
                            "{:.3g} mm); refine the particles or use the velocity contact",
                            0.5e3 * H, 1e3 * h));
  D.reach = std::max(D.reach, 1);
  for (int B = 0; B < 2; ++B) {
    // A point of the other body A at its touching height (d_A + d_B) / 2 above B's outer layer.
    const LatticeFraction f = latticeFraction(D.kernel, D.spacing[B], 0.5 * (D.spacing[0] + D.spacing[1]));
    D.phiStar[B] = f.phi;
    D.slope[B] = f.slope;
  }
  D.invDp2 = 1.0 / (dp * dp);
  return D;
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

// Forces of the density law at the positions of the step's start, into the
// grid force f_I of each point's own body before the momentum update (eq 3),
// as the pair penalty's. Two sweeps over the pairs within H (each visited
// once, from the cell of its body-0 point; reactions of other threads in
// their own buffers): the first accumulates at every candidate the other
// body's phi, grad phi, a bound on the Hessian of phi and d phi / dt and
// records the pair (densitySweepCell); after the law per point (a = c
// U'(delta) / s, the energy, the tangent stiffness and the step limit;
// densityLawAt) the second applies the central pair forces and the friction
// (densityPairForces).
void MpmSolver::densityForces() {
  PairPenalty& P = *penalty_;
  DensityLaw& D = *P.density_;
  P.bin(nearCell_.data(), body_.data(), size(), nodes_);
  const std::size_t nc = P.cand_.size(), first1 = P.first1_;
  resetDensityScratch();
  const double dt0 = dt_, mu = cfg_.friction;
  const std::size_t ncell = P.cells0_.size();
  std::atomic<std::size_t> passed{0};  // 1 + a point beyond the barrier's pole
#pragma omp parallel num_threads(nthreads_)
  {
#ifdef _OPENMP
    const std::size_t tid = static_cast<std::size_t>(omp_get_thread_num());
#else
    const std::size_t tid = 0;
#endif
    D.pairs[tid].clear();
    P.cellBoxes(P_[0].x, sizeof(Point) / sizeof(double), nodes_);
    const auto [racc, from] = reactionSink(D.acc.data(), D.react[tid], 8, tid, first1, nc);  // slot s at racc[8 (s - from)]
    // Sweep 1: phi, grad phi, Hessian bound, rate and pair count at both points of each pair within H.
#pragma omp for schedule(static)
    for (std::size_t ic = 0; ic < ncell; ++ic) densitySweepCell(P.cells0_[ic], tid, racc, from);
    // The law per point (after the barrier of the search).
#pragma omp for schedule(static, 64)
    for (std::size_t s = 0; s < nc; ++s) densityLawAt(s, tid, dt0, passed);
    const PenaltyTally all = P.sum();
    const double dt = cfg_.fixedTimeStep > 0 ? dt0 : std::min(dt0, P.limit(all, cfg_.penaltyStepFactor));
    const bool friction = mu > 0.0 && all.pairs > 0;
    if (friction) densityFrictionInputs(tid);
    densityPairForces(tid, friction, mu, dt);
#pragma omp barrier
    scatterContact(tid);
    if (tid == 0) dt_ = dt;
  }
  P.tally_ = P.sum();
  if (const std::size_t bad = passed.load()) {
    const std::size_t p = bad - 1;
    throw SolverError(fmt::format(
        "mpm: point {} at ({:.4g}, {:.4g}, {:.4g}) mm passed the density contact's barrier into the other body at t = "
        "{:.6g} s; raise penaltyFactor or lower penaltyStepFactor",
        p, 1e3 * P_[p].x[0], 1e3 * P_[p].x[1], 1e3 * P_[p].x[2], time_));
  }
}

// densityForces: the scratch of the step sized for the candidates and
// threads, the sums zeroed.
void MpmSolver::resetDensityScratch() {
  PairPenalty& P = *penalty_;
  DensityLaw& D = *P.density_;
  const std::size_t nc = P.cand_.size(), nthreads = P.thread_.size();
  P.force_.assign(3 * nc, 0.0);
  P.reaction_.resize(nthreads);
  for (auto& r : P.reaction_) r.clear();
  for (auto& t : P.thread_) t = PenaltyTally{};
  P.resetFriction();
  P.vfield_.resize(3 * nc);
  D.acc.assign(8 * nc, 0.0);
  D.react.resize(nthreads);
  for (auto& r : D.react) r.clear();
  D.a.assign(nc, 0.0);
  D.normal.assign(3 * nc, 0.0);
  if (cfg_.friction > 0.0) D.load.assign(2 * nc, 0.0);
  D.pairs.resize(nthreads);
  P.need_.assign(nc, 0);
}

// densityForces: the occupied body-1 cells within the law's reach of the
// body-0 cell c0 whose points' box lies within H of c0's (slot ranges lo,
// hi and their boxes bb, as PairPenalty::nearCells); returns how many.
[[gnu::always_inline]] inline int MpmSolver::densityNearCells(std::size_t c0, std::uint32_t* lo, std::uint32_t* hi,
                                                              const double** bb) const {
  const PairPenalty& P = *penalty_;
  const DensityLaw& D = *P.density_;
  const std::size_t n1 = static_cast<std::size_t>(nn_[1]), n2 = static_cast<std::size_t>(nn_[2]);
  const long long lim[3] = {nn_[0], nn_[1], nn_[2]};
  const double H2 = D.kernel.H * D.kernel.H;
  const int nb = P.nearCells(c0, D.reach, nodes_, n1, n2, lim, lo, hi, bb);
  // Bounding box of c0's points; keep the body-1 cells whose box is within H of it.
  double b0[6] = {kInf, kInf, kInf, -kInf, -kInf, -kInf};
  for (std::uint32_t sp = P.start_[c0]; sp < P.start_[c0 + 1]; ++sp)
    for (int d = 0; d < 3; ++d) {
      b0[d] = std::min(b0[d], P_[P.items_[sp]].x[d]);
      b0[3 + d] = std::max(b0[3 + d], P_[P.items_[sp]].x[d]);
    }
  int kept = 0;
  for (int b = 0; b < nb; ++b) {
    double g2 = 0.0;  // squared distance of the two boxes
    for (int d = 0; d < 3; ++d) {
      const double g = std::max({0.0, bb[b][d] - b0[3 + d], b0[d] - bb[b][3 + d]});
      g2 += g * g;
    }
    if (!(g2 < H2)) continue;
    lo[kept] = lo[b];
    hi[kept] = hi[b];
    bb[kept] = bb[b];
    ++kept;
  }
  return kept;
}

// densityForces, sweep 1 from the body-0 cell c0 on thread tid: for each
// pair within H, phi, grad phi, the Hessian bound, the rate d phi / dt and
// the pair counts at both points (body-1 slot s at racc[8 (s - from)]), the
// pair in the thread's list, the overlap in its tally.
[[gnu::always_inline]] inline void MpmSolver::densitySweepCell(std::size_t c0, std::size_t tid, double* racc,
                                                               std::size_t from) {
  PairPenalty& P = *penalty_;
  DensityLaw& D = *P.density_;
  const double H = D.kernel.H, H2 = H * H;
  PenaltyTally& T = P.thread_[tid];
  auto& Pairs = D.pairs[tid];
  std::uint32_t lo[343], hi[343];
  const double* bb[343];
  const int nb = densityNearCells(c0, lo, hi, bb);
  for (std::uint32_t sp = P.start_[c0]; sp < P.start_[c0 + 1]; ++sp) {
    const std::size_t p = P.items_[sp];
    const double* xp = P_[p].x;
    const double* vp = P_[p].v;
    const double Vp = P_[p].vol0;
    double* ap = &D.acc[8 * sp];
    for (int b = 0; b < nb; ++b) {
      const double* bx = bb[b];
      // squared distance of p to the cell's box: beyond H no pair there
      const double gx = std::max({0.0, bx[0] - xp[0], xp[0] - bx[3]});
      const double gy = std::max({0.0, bx[1] - xp[1], xp[1] - bx[4]});
      const double gz = std::max({0.0, bx[2] - xp[2], xp[2] - bx[5]});
      if (!(gx * gx + gy * gy + gz * gz < H2)) continue;
      for (std::uint32_t sq = lo[b]; sq < hi[b]; ++sq) {
        const std::size_t q = P.items_[sq];
        const double dx = xp[0] - P_[q].x[0], dy = xp[1] - P_[q].x[1], dz = xp[2] - P_[q].x[2];
        const double r2 = dx * dx + dy * dy + dz * dz;
        if (!(r2 < H2)) continue;
        const double r = std::sqrt(r2);
        const double w = D.kernel.value(r), c = D.kernel.slopeOverR(r), hb = D.kernel.hessianBound(r);
        const double Vq = P_[q].vol0;
        // d/dt of |x_p - x_q|-terms: (dx . (v_p - v_q)); grad_p W = -c dx, grad_q W = c dx.
        const double dv = dx * (vp[0] - P_[q].v[0]) + dy * (vp[1] - P_[q].v[1]) + dz * (vp[2] - P_[q].v[2]);
        ap[0] += Vq * w;
        ap[1] -= Vq * c * dx;
        ap[2] -= Vq * c * dy;
        ap[3] -= Vq * c * dz;
        ap[4] += Vq * hb;
        ap[5] -= Vq * c * dv;
        ap[6] += 1.0;
        double* aq = racc + 8 * (sq - from);
        aq[0] += Vp * w;
        aq[1] += Vp * c * dx;
        aq[2] += Vp * c * dy;
        aq[3] += Vp * c * dz;
        aq[4] += Vp * hb;
        aq[5] -= Vp * c * dv;
        aq[6] += 1.0;
        const double d = P.radius_[p] + P.radius_[q];  // overlap of the two points' volumes (reported)
        T.penetration = std::max(T.penetration, d - r);
        if (r < d) {  // pairs within the contact distance: the friction's pairs
          ap[7] += 1.0;
          aq[7] += 1.0;
        }
        Pairs.push_back({sp, static_cast<std::uint32_t>(sq), c});
      }
    }
  }
}

// densityForces, the law at slot s on thread tid (after sweep 1; a body-1
// slot adds the other threads' sums first): the equivalent overlap and its
// rate, a = c U'(delta) / s, the energy, tangent stiffness and approach into
// the thread's tally; a point beyond the barrier's pole is recorded in passed.
[[gnu::always_inline]] inline void MpmSolver::densityLawAt(std::size_t s, std::size_t tid, double dt0,
                                                           std::atomic<std::size_t>& passed) {
  PairPenalty& P = *penalty_;
  DensityLaw& D = *P.density_;
  const std::size_t first1 = P.first1_, nthreads = P.thread_.size();
  PenaltyTally& T = P.thread_[tid];
  double* A = &D.acc[8 * s];
  if (s >= first1)
    for (std::size_t t = 1; t < nthreads; ++t)
      if (!D.react[t].empty())
        for (int j = 0; j < 8; ++j) A[j] += D.react[t][8 * (s - first1) + static_cast<std::size_t>(j)];
  if (!(A[0] > 0.0)) return;
  const std::size_t p = P.items_[s];
  const int B = 1 - body_[p];
  const double sl = D.slope[B];
  const double delta = (A[0] - D.phiStar[B]) / sl, rate = A[5] / sl;  // equivalent overlap and its rate
  const double d = P.radius_[p] + 0.5 * D.spacing[B];
  if (delta > 0.0) {
    if (!(delta < d)) {
      std::size_t none = 0;
      passed.compare_exchange_strong(none, p + 1);
      return;
    }
    const double cq = 2.0 * P.radius_[p] * P.radius_[p] * D.invDp2;  // V^(2/3) / (2 d_p^2)
    const double f = P.pairForce(delta, d);
    D.a[s] = cq * f / sl;
    T.energy += cq * P.pairEnergy(delta, d);
    const double g2 = (A[1] * A[1] + A[2] * A[2] + A[3] * A[3]) / (sl * sl);
    T.tangent = std::max(T.tangent, cq * (P.pairTangent(delta, d) * g2 + f * A[4] / sl));
    T.pairs += 1;
    if (rate > 0.0) T.travel = std::min(T.travel, (d - delta) / rate);
  } else if (rate > 0.0 && -delta < 2.0 * rate * dt0) {
    T.close += 1;  // would touch within two steps at the current rate
    T.travel = std::min(T.travel, (d - delta) / rate);
  }
}

// densityForces, friction (all threads, inside the parallel region): the
// field velocity and the surface normal at each point within H of the other
// body, once, while any point is in contact; then the normal load of each
// point, from all its pairs and from those within the contact distance (the
// friction's pairs; reactions as in sweep 1), summed after a barrier.
void MpmSolver::densityFrictionInputs(std::size_t tid) {
  PairPenalty& P = *penalty_;
  DensityLaw& D = *P.density_;
  const std::size_t nc = P.cand_.size(), first1 = P.first1_, nthreads = P.thread_.size();
  const std::size_t NR = static_cast<std::size_t>(nr_);
  const double* rec0 = buf_[0].rec.data();
#pragma omp for schedule(static, 16)
  for (std::size_t s = 0; s < nc; ++s)
    if (D.acc[8 * s] > 0.0) {
      fieldVelocity(P.items_[s], rec0, NR, &P.vfield_[3 * s]);
      if (!surfaceNormal(P_[P.items_[s]].x, &D.normal[3 * s])) D.normal[3 * s] = D.normal[3 * s + 1] = D.normal[3 * s + 2] = 0.0;
    }
  const auto [rl, lfrom] = reactionSink(D.load.data(), D.react[tid], 2, tid, first1, nc);
  for (const DensityLaw::Pair& C : D.pairs[tid]) {
    const double ap = D.a[C.sp], aq = D.a[C.sq];
    if (ap == 0.0 && aq == 0.0) continue;
    const std::size_t p = P.items_[C.sp], q = P.items_[C.sq];
    const double dx = P_[p].x[0] - P_[q].x[0], dy = P_[p].x[1] - P_[q].x[1], dz = P_[p].x[2] - P_[q].x[2];
    const double r2 = dx * dx + dy * dy + dz * dz, d = P.radius_[p] + P.radius_[q];
    const double f = (aq * P_[p].vol0 + ap * P_[q].vol0) * C.c * std::sqrt(r2);
    const double close = r2 < d * d ? f : 0.0;
    D.load[2 * C.sp] += f;
    D.load[2 * C.sp + 1] += close;
    rl[2 * (C.sq - lfrom)] += f;
    rl[2 * (C.sq - lfrom) + 1] += close;
  }
#pragma omp barrier
#pragma omp for schedule(static, 64)
  for (std::size_t s = first1; s < nc; ++s)
    for (std::size_t t = 1; t < nthreads; ++t)
      if (!D.react[t].empty()) {
        D.load[2 * s] += D.react[t][2 * (s - first1)];
        D.load[2 * s + 1] += D.react[t][2 * (s - first1) + 1];
      }
}

// densityForces, sweep 2 over thread tid's pairs: the central pair forces
// f_p = (a_q V_p + a_p V_q) (-W'(r)/r) (x_p - x_q) and, with friction, the
// Coulomb force at step dt; f_p on p, -f_p on q (reactions as in sweep 1).
void MpmSolver::densityPairForces(std::size_t tid, bool friction, double mu, double dt) {
  PairPenalty& P = *penalty_;
  DensityLaw& D = *P.density_;
  double& Wf = P.friction_[8 * tid];
  const auto [react, reactFrom] = reactionSink(P.force_.data(), P.reaction_[tid], 3, tid, P.first1_, P.cand_.size());
  for (const DensityLaw::Pair& C : D.pairs[tid]) {
    const double ap = D.a[C.sp], aq = D.a[C.sq];
    if (ap == 0.0 && aq == 0.0) continue;
    const std::size_t p = P.items_[C.sp], q = P.items_[C.sq];
    const double dx[3] = {P_[p].x[0] - P_[q].x[0], P_[p].x[1] - P_[q].x[1], P_[p].x[2] - P_[q].x[2]};
    const double fm = (aq * P_[p].vol0 + ap * P_[q].vol0) * C.c;
    double fp[3] = {fm * dx[0], fm * dx[1], fm * dx[2]};
    const double r2 = dx[0] * dx[0] + dx[1] * dx[1] + dx[2] * dx[2], dpq = P.radius_[p] + P.radius_[q];
    if (friction && fm > 0.0 && r2 < dpq * dpq) {
      // Coulomb on the pairs within the contact distance (eqs 19-21; the
      // friction force is not central, so its couple (x_p - x_q) x f_t is
      // kept to a lever of one spacing, as the pair penalty's): normal force
      // = the pair force along the bodies' normal (the mean of the two
      // points' normals, pointing into p's body 0) scaled by the points'
      // load over that of their close pairs (so each point's Coulomb limits
      // sum to mu times its whole normal load), sliding velocity of the two
      // grid fields; the sticking force m_r |v_t| / dt shared among the close
      // pairs of the point with more of them (their sum sticks it at most once).
      const double* mp = &D.normal[3 * C.sp];
      const double* mq = &D.normal[3 * C.sq];
      double m[3] = {-(mp[0] + mq[0]), -(mp[1] + mq[1]), -(mp[2] + mq[2])};
      const double mm = std::sqrt(m[0] * m[0] + m[1] * m[1] + m[2] * m[2]);
      const double* Lp = &D.load[2 * C.sp];
      const double* Lq = &D.load[2 * C.sq];
      const double scale = 0.5 * (Lp[0] / Lp[1] + Lq[0] / Lq[1]);
      const double fN = mm > 0.0 ? scale * (fp[0] * m[0] + fp[1] * m[1] + fp[2] * m[2]) / mm : 0.0;
      if (fN > 0.0) {
        for (double& x : m) x /= mm;
        const double mr = P_[p].mass * P_[q].mass / (P_[p].mass + P_[q].mass);
        const double share = 1.0 / std::max(D.acc[8 * C.sp + 7], D.acc[8 * C.sq + 7]);
        Wf += contact::coulombPair(m, fN, &P.vfield_[3 * C.sp], &P.vfield_[3 * C.sq], share * mr, mu, dt, fp);
      }
    }
    for (int k = 0; k < 3; ++k) {
      P.force_[3 * C.sp + k] += fp[k];
      react[3 * (C.sq - reactFrom) + k] -= fp[k];
    }
  }
}

// Stored energy at the positions after the step (as the strain energy of the
// report) from the pairs within H at its start (a pair that came within H
// during the step adds W of order (v dt / H)^3 at the rim); serial, in the
// order of the threads' pair lists (the same for any thread count).
void MpmSolver::densityEnergyAfterStep() {
  PairPenalty& P = *penalty_;
  DensityLaw& D = *P.density_;
  const std::size_t nc = P.cand_.size();
  D.phiEnd.assign(nc, 0.0);
  for (const auto& list : D.pairs)
    for (const DensityLaw::Pair& C : list) {
      const std::size_t p = P.items_[C.sp], q = P.items_[C.sq];
      const double dx = P_[p].x[0] - P_[q].x[0], dy = P_[p].x[1] - P_[q].x[1], dz = P_[p].x[2] - P_[q].x[2];
      const double w = D.kernel.value(std::sqrt(dx * dx + dy * dy + dz * dz));
      D.phiEnd[C.sp] += P_[q].vol0 * w;
      D.phiEnd[C.sq] += P_[p].vol0 * w;
    }
  double e = 0.0, kt = 0.0;
  for (std::size_t s = 0; s < nc; ++s) {
    if (!(D.phiEnd[s] > 0.0)) continue;
    const std::size_t p = P.items_[s];
    const int B = 1 - body_[p];
    const double delta = (D.phiEnd[s] - D.phiStar[B]) / D.slope[B], d = P.radius_[p] + 0.5 * D.spacing[B];
    if (delta > 0.0 && delta < d) {
      const double cq = 2.0 * P.radius_[p] * P.radius_[p] * D.invDp2;
      e += cq * P.pairEnergy(delta, d);
      kt = std::max(kt, cq * P.pairTangent(delta, d));
    }
  }
  P.tally_.energy = e;
  P.tally_.tangent = std::max(P.tally_.tangent, kt);
}

}  // namespace needlesim::mpm
