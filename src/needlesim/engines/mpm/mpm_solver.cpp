// Explicit MPM core: seed 000 eqs 1-4 (mapping and update), 14-21 (grid
// contact), 25-28 (time step, mass scaling). See docs/models/mpm.md.
#include "needlesim/engines/mpm/mpm_solver.hpp"
#include "needlesim/engines/mpm/support_lanes.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstring>
#include <ctime>
#include <limits>
#include <numbers>
#include <tuple>

#include "needlesim/contact/coulomb.hpp"
#include "needlesim/core/error.hpp"
#include "needlesim/materials/fast_stress.hpp"
#include "needlesim/needle/surface_mesh.hpp"
#include "needlesim/engines/mpm/grid_kernels.hpp"
#include "needlesim/engines/mpm/penalty_contact.hpp"
#include "needlesim/engines/mpm/surface_estimate.hpp"

#ifdef _OPENMP
#include <omp.h>
#endif

namespace needlesim::mpm {

namespace {
constexpr double kInf = std::numeric_limits<double>::infinity();
// Seconds on the steady clock (the phase times of step()).
inline double wallSeconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}
// CPU seconds of the process, all threads (POSIX).
inline double cpuSeconds() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}
// Four lanes of a grid record as a GCC vector: two SSE2 operations in the
// baseline x86-64 build, one AVX2/FMA operation in the x86-64-v3 clones of the
// hot kernels (NEEDLESIM_MPM_CLONES). Unaligned, may alias double.
using lanes::A4;  // materials/stress_lanes.hpp
// Always inlined, also at -O0: a call would pass A4 by the baseline ABI
// (memory) from an AVX2 clone that expects it in a register.
[[gnu::always_inline]] inline A4 ld(const double* p) { return *reinterpret_cast<const A4*>(p); }
[[gnu::always_inline]] inline void add(double* p, A4 v) { *reinterpret_cast<A4*>(p) += v; }
// 0.0 that the compiler cannot see through: lanes packed with it compile to
// unpack/insert instructions instead of the VEX "vmovq xmm, xmm" that
// valgrind 3.19 cannot decode (callgrind counts of docs/performance.md).
inline double opaqueZero() {
  double z = 0.0;
#if defined(__GNUC__) && defined(__x86_64__)
  asm("" : "+x"(z));
#endif
  return z;
}
// Grid record offsets and shape functions (grid_kernels.hpp).
using grid::kM, grid::kP, grid::kF, grid::kG, grid::kX;

// Function multiversioning of the particle-grid kernels: a baseline x86-64
// clone and an x86-64-v3 (AVX2, FMA) clone chosen at load time, so the default
// build runs on any x86-64 (no -march=native). Off with NEEDLESIM_MPM_NO_CLONES.
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && !defined(NEEDLESIM_MPM_NO_CLONES)
#define MPM_CLONES __attribute__((target_clones("arch=x86-64-v3", "default")))
#else
#define MPM_CLONES
#endif

// Two bodies: the word of cell c of body b in the bit rows of
// markNearBodies (W words per body and row, both bodies in a row), and its bit.
inline std::size_t cellWord(grid::Cell c, std::size_t b, std::size_t W) { return (2 * c.row + b) * W + c.k / 64; }
inline std::uint64_t cellBit(grid::Cell c) { return std::uint64_t{1} << (c.k % 64); }

// Software prefetch of the record of a point a few visits ahead, the cache
// lines of mask Lines (bit l: line l of the 256-byte Point): perf showed the
// particle passes stalled on the first touch of a record's lines (the two-body
// scatter 32 % of its time on the stress line), which the hardware prefetchers
// do not fetch early enough for records visited in block order.
constexpr std::size_t kPrefetchAhead = 6;
template <unsigned Lines>
[[gnu::always_inline]] inline void prefetchRecord(const void* rec) {
  const char* c = static_cast<const char*>(rec);
  if constexpr ((Lines & 1u) != 0) __builtin_prefetch(c, 1, 3);
  if constexpr ((Lines & 2u) != 0) __builtin_prefetch(c + 64, 1, 3);
  if constexpr ((Lines & 4u) != 0) __builtin_prefetch(c + 128, 1, 3);
  if constexpr ((Lines & 8u) != 0) __builtin_prefetch(c + 192, 1, 3);
}

inline int threadId() {
#ifdef _OPENMP
  return omp_get_thread_num();
#else
  return 0;
#endif
}

inline int teamSize() {
#ifdef _OPENMP
  return omp_get_num_threads();
#else
  return 1;
#endif
}

}  // namespace

// ---------------------------------------------------------------- materials

MpmMaterial MpmMaterial::fromSpec(const materials::MaterialSpec& spec) {
  MpmMaterial m;
  m.law = materials::Hyperelastic::fromSpec(spec);
  m.density = spec.density;
  return m;
}

// ---------------------------------------------------------------- rigid bodies

double RigidBody::distance(const Vec3& x, Vec3* n, int* part) const {
  if (kind == Kind::Plane) {
    if (n) *n = normal;
    if (part) *part = 0;
    return (x - point).dot(normal);
  }
  const Vec3& e = axis;
  const Vec3 c = axisPoint();
  const Vec3 rel = x - c;
  const double s = -rel.dot(e);  // distance behind the tip plane along the axis
  Vec3 rv = rel + s * e;         // radial vector
  double r = rv.norm();
  Vec3 er = r > 1e-14 ? Vec3(rv / r) : bevelSide;
  const double dCyl = r - radius;
  double dTip;
  Vec3 nTip;
  switch (tip) {
    case Tip::Conical: {
      const double cb = std::cos(tipAngle), sb = std::sin(tipAngle);
      if (s * cb + r * sb <= 0.0) {  // nearest point is the apex
        dTip = rel.norm();
        nTip = dTip > 1e-14 ? Vec3(rel / dTip) : e;
      } else {
        dTip = r * cb - s * sb;
        nTip = cb * er + sb * e;
      }
      break;
    }
    case Tip::Bevel: {
      nTip = std::sin(tipAngle) * e + std::cos(tipAngle) * bevelSide;  // face of the bevel
      dTip = (x - point).dot(nTip);
      break;
    }
    case Tip::Blunt:
    default:
      nTip = e;
      dTip = -s;
      break;
  }
  if (dTip >= dCyl) {
    if (n) *n = nTip;
    if (part) *part = 1;
    return dTip;
  }
  if (n) *n = er;
  if (part) *part = 0;
  return dCyl;
}

// ---------------------------------------------------------------- setup

MpmSolver::MpmSolver(const MpmConfig& cfg) : cfg_(cfg) {
  if (!(cfg_.h > 0)) throw Error("mpm: grid spacing must be > 0");
  if (cfg_.bodies < 1 || cfg_.bodies > 2) throw Error("mpm: 1 or 2 deformable bodies are supported");
  for (int d = 0; d < 3; ++d) {
    if (cfg_.cells[d] < 2) throw Error("mpm: the grid needs at least 2 cells along each axis");
    nn_[d] = cfg_.cells[d] + 1;
  }
  nodes_ = static_cast<std::size_t>(nn_[0]) * nn_[1] * nn_[2];
#ifdef _OPENMP
  nthreads_ = cfg_.threads > 0 ? cfg_.threads : omp_get_max_threads();
#else
  nthreads_ = 1;
#endif
}

int MpmSolver::addMaterial(const MpmMaterial& m) {
  mats_.push_back(m);
  return static_cast<int>(mats_.size()) - 1;
}

int MpmSolver::addRigid(const RigidBody& r) {
  rigids_.push_back(r);
  return static_cast<int>(rigids_.size()) - 1;
}

void MpmSolver::checkIds(int material, int body) const {
  if (material < 0 || material >= static_cast<int>(mats_.size())) throw Error("mpm: unknown material index");
  if (body < 0 || body >= cfg_.bodies) throw Error("mpm: body index out of range");
}

Lattice::Lattice(const Vec3& lo_, const Vec3& hi, double dp) : lo(lo_) {
  for (int d = 0; d < 3; ++d) {
    n[static_cast<std::size_t>(d)] = std::max(1, static_cast<int>(std::lround((hi[d] - lo[d]) / dp)));
    sp[d] = (hi[d] - lo[d]) / n[static_cast<std::size_t>(d)];
  }
}

std::size_t MpmSolver::addBlock(const Vec3& lo, const Vec3& hi, double dp, int material, int body,
                                const Vec3& velocity) {
  checkIds(material, body);
  const Lattice L(lo, hi, dp);
  const std::size_t first = size();
  const double vol = L.sp.prod();
  const double m = mats_[static_cast<std::size_t>(material)].density * vol * cfg_.massScaling;
  for (int i = 0; i < L.n[0]; ++i)
    for (int j = 0; j < L.n[1]; ++j)
      for (int k = 0; k < L.n[2]; ++k) pushParticle(L.point(i, j, k), velocity, m, vol, material, body);
  dp_ = dp_ > 0 ? std::min(dp_, L.sp.minCoeff()) : L.sp.minCoeff();
  return first;
}

std::size_t MpmSolver::addLattice(const Lattice& L, const std::vector<int>& material, const std::vector<int>& body) {
  const std::size_t first = size();
  const double vol = L.sp.prod();
  for (int i = 0; i < L.n[0]; ++i)
    for (int j = 0; j < L.n[1]; ++j)
      for (int k = 0; k < L.n[2]; ++k) {
        const std::size_t q = L.index(i, j, k);
        if (material[q] < 0) continue;
        checkIds(material[q], body[q]);
        const double m = mats_[static_cast<std::size_t>(material[q])].density * vol * cfg_.massScaling;
        pushParticle(L.point(i, j, k), Vec3::Zero(), m, vol, material[q], body[q]);
      }
  if (size() > first) dp_ = dp_ > 0 ? std::min(dp_, L.sp.minCoeff()) : L.sp.minCoeff();
  return first;
}

std::size_t MpmSolver::addParticle(const Vec3& x, double volume, int material, int body, const Vec3& velocity) {
  checkIds(material, body);
  if (!(volume > 0) || !std::isfinite(volume)) throw Error("mpm: a material point needs a positive volume");
  const double m = mats_[static_cast<std::size_t>(material)].density * volume * cfg_.massScaling;
  pushParticle(x, velocity, m, volume, material, body);
  const double sp = std::cbrt(volume);
  dp_ = dp_ > 0 ? std::min(dp_, sp) : sp;
  return size() - 1;
}

void MpmSolver::reassign(std::size_t p, int material, int body) {
  checkIds(material, body);
  if (finalized_) throw Error("mpm: a point changes material or body only before finalize");
  P_[p].mass = mats_[static_cast<std::size_t>(material)].density * P_[p].vol0 * cfg_.massScaling;
  body_[p] = static_cast<std::uint8_t>(body);
  mat_[p] = static_cast<std::uint8_t>(material);
}

void MpmSolver::pushParticle(const Vec3& x, const Vec3& v, double mass, double volume, int material, int body) {
  Point q{};
  for (int d = 0; d < 3; ++d) {
    q.x[d] = x[d];
    q.v[d] = v[d];
  }
  q.mass = mass;
  q.vol0 = volume;
  q.vol = volume;
  for (int c = 0; c < 9; ++c) q.F[c] = c % 4 == 0 ? 1.0 : 0.0;
  P_.push_back(q);
  body_.push_back(static_cast<std::uint8_t>(body));
  mat_.push_back(static_cast<std::uint8_t>(material));
}

void MpmSolver::finalize() {
  const int B = cfg_.bodies;
  const std::size_t R = rigids_.size();
  nr_ = 8;
  buf_.resize(1);
  for (auto& b : buf_) {
    b.rec.assign(static_cast<std::size_t>(nr_) * B * nodes_, 0.0);
    b.grad.assign(B > 1 ? 8 * 2 * nodes_ : 0, 0.0);
    b.gmin.assign(R * nodes_, kInf);
  }
  materialFriction_.clear();
  if (std::any_of(mats_.begin(), mats_.end(), [](const MpmMaterial& m) { return m.rigidFriction >= 0.0; })) {
    for (const MpmMaterial& m : mats_) materialFriction_.push_back(m.rigidFriction);
    buf_[0].gmat.assign(R * nodes_, 0);
    for (const RigidBody& r : rigids_)
      if (r.surfaceContact) throw Error("mpm: the CFEMP contact takes the rigid body's friction, not the materials'");
  }
  nearCell_.assign(B > 1 ? size() : 0, kNotNear);
  occFresh_ = false;  // markNearBodies marks the cells from the positions
  vel_.assign(8 * B * nodes_, 0.0);
  gridClean_ = true;
  order_.resize(size());
  for (std::size_t p = 0; p < size(); ++p) order_[p] = static_cast<std::uint32_t>(p);
  planned_ = false;
  scatterThreads_ = 1;
  sorts_ = 0;
  active_.assign(R * nodes_, 0);
  rnormal_.assign(3 * R * nodes_, 0.0);
  rforce_.assign(R, RigidForce{});
  if (cfg_.contactGap < 0) cfg_.contactGap = 0.5 * dp_;
  surf_.assign(R, Surface{});
  for (std::size_t r = 0; r < R; ++r)
    if (rigids_[r].surfaceContact) buildSurface(r);
  // Centroid separation of two touching half-spaces seen from a node on the
  // interface: 2 x 0.406 h (quadratic B-spline), 2 h / 3 (linear).
  pairGap_ = (cfg_.shape == Shape::Linear ? 2.0 / 3.0 : 0.8125) * cfg_.h * cfg_.pairGapFactor;
  surfaceEst_.reset();
  if (cfg_.pairGapRule == PairGapRule::Surface) {
    surfaceEst_.emplace(cfg_.shape != Shape::Linear);
    pairGap_ = cfg_.pairGapTolerance * cfg_.h;
  }
  setUpPairContact();
  setUpBoundaries();
  checkInitialState();
  finalized_ = true;
}

// Penalty or density contact of two bodies (penalty_contact.hpp,
// density_contact.hpp): stiffness kappa M d_p.
void MpmSolver::setUpPairContact() {
  const int B = cfg_.bodies;
  penalty_.reset();
  if (B > 1 && cfg_.bodyContact != BodyContact::Velocity) {
    double M = 0.0;
    for (const MpmMaterial& m : mats_) {
      M = std::max(M, m.law.initialBulk() + 4.0 / 3.0 * m.law.initialShear());
    }
    double mmin = P_.empty() ? 0.0 : kInf;
    for (const Point& q : P_) mmin = std::min(mmin, q.mass);
    std::vector<double> radius(size());
    double rmax = 0.0;
    for (std::size_t p = 0; p < size(); ++p) {
      radius[p] = 0.5 * std::cbrt(P_[p].vol0);
      rmax = std::max(rmax, radius[p]);
    }
    if (2 * rmax > cfg_.h * (1 + 1e-9))
      throw Error(fmt::format("mpm: the penalty contact needs particle spacings of at most the grid spacing ({:.3g} mm "
                              "> {:.3g} mm); refine the particles or use the velocity contact",
                              2e3 * rmax, 1e3 * cfg_.h));
    std::optional<DensityLaw> law;
    if (cfg_.bodyContact == BodyContact::Density) law.emplace(makeDensityLaw(radius, body_, dp_, cfg_.h));
    penalty_.emplace(cfg_.penaltyFactor * M * dp_, std::move(radius), 0.5 * mmin, nthreads_);
    if (law) penalty_->useDensity(std::move(*law));
  }

}

// Boundary conditions on the nodes on or beyond each face of the box.
void MpmSolver::setUpBoundaries() {
  fixMask_.assign(nodes_, 0);
  dashpot_.assign(3 * nodes_, 0.0);
  const double tol = 1e-6 * cfg_.h;
  const MpmMaterial* m0 = mats_.empty() ? nullptr : &mats_[0];
  double rho = 0, cp = 0, cs = 0;
  if (m0) {
    rho = m0->density * cfg_.massScaling;
    const double K = m0->law.initialBulk(), mu = m0->law.initialShear();
    cp = std::sqrt((K + 4.0 / 3.0 * mu) / rho);
    cs = std::sqrt(mu / rho);
  }
  for (int i = 0; i < nn_[0]; ++i)
    for (int j = 0; j < nn_[1]; ++j)
      for (int k = 0; k < nn_[2]; ++k) {
        const std::size_t I = (static_cast<std::size_t>(i) * nn_[1] + j) * nn_[2] + k;
        const int idx[3] = {i, j, k};
        for (int f = 0; f < 6; ++f) {
          const int d = f / 2;
          const double x = cfg_.origin[d] + idx[d] * cfg_.h;
          const bool beyond = (f % 2 == 0) ? x <= cfg_.boxLo[d] + tol : x >= cfg_.boxHi[d] - tol;
          if (!beyond) continue;
          switch (cfg_.faces[static_cast<std::size_t>(f)]) {
            case FaceBC::Fixed: fixMask_[I] |= 7; break;
            case FaceBC::Roller: fixMask_[I] |= static_cast<std::uint8_t>(1 << d); break;
            case FaceBC::NonReflecting: {
              // Lysmer-Kuhlemeyer dashpots on the face nodes (tributary area h^2).
              const bool onFace = std::abs(x - ((f % 2 == 0) ? cfg_.boxLo[d] : cfg_.boxHi[d])) < 0.5 * cfg_.h;
              if (!onFace) break;
              for (int c = 0; c < 3; ++c)
                dashpot_[3 * I + c] += rho * (c == d ? cp : cs) * cfg_.h * cfg_.h;
              break;
            }
            case FaceBC::Free: break;
          }
        }
      }
  for (const auto& n : cfg_.heldNodes) {
    if (n[0] < 0 || n[1] < 0 || n[2] < 0 || n[0] >= nn_[0] || n[1] >= nn_[1] || n[2] >= nn_[2]) continue;
    fixMask_[(static_cast<std::size_t>(n[0]) * nn_[1] + n[1]) * nn_[2] + n[2]] |= 7;
  }

}

// Every particle lies inside the grid; the initial wave speed.
void MpmSolver::checkInitialState() {
  maxSpeed_ = 0.0;
  const int S = cfg_.shape == Shape::Linear ? 2 : 3;
  const double invh = 1.0 / cfg_.h;
  for (std::size_t p = 0; p < size(); ++p) {
    const double xs[3] = {P_[p].x[0], P_[p].x[1], P_[p].x[2]};
    for (int d = 0; d < 3; ++d) {
      double xi = (xs[d] - cfg_.origin[d]) * invh;
      int b = S == 2 ? static_cast<int>(std::floor(xi)) : static_cast<int>(std::floor(xi - 0.5));
      if (b < 0 || b > nn_[d] - S) fail(p, 3);
    }
    double W, c;
    stress(p, defGrad(p), W, c);
    maxSpeed_ = std::max(maxSpeed_, c + velocity(p).norm());
  }
}

// The node's material (gmat) is the one p2g recorded this step: read only at
// nodes whose gap minimum it lowered (gridUpdate, remapUpdate of that step).
double MpmSolver::rigidFriction(std::size_t r, std::size_t I) const {
  if (materialFriction_.empty()) return rigids_[r].friction;
  const double mu = materialFriction_[buf_[0].gmat[r * nodes_ + I]];
  return mu >= 0.0 ? mu : rigids_[r].friction;
}

Vec3 MpmSolver::nodePosition(std::size_t I) const {
  const std::size_t n12 = static_cast<std::size_t>(nn_[1]) * static_cast<std::size_t>(nn_[2]);
  const std::size_t n2 = static_cast<std::size_t>(nn_[2]);
  return cfg_.origin + cfg_.h * Vec3(static_cast<double>(I / n12), static_cast<double>((I / n2) % nn_[1]),
                                     static_cast<double>(I % n2));
}

Mat3 MpmSolver::defGrad(std::size_t p) const {
  Mat3 F;
  for (int c = 0; c < 9; ++c) F(c / 3, c % 3) = P_[p].F[c];
  return F;
}

Mat3 MpmSolver::cauchy(std::size_t p) const {
  Mat3 s;
  s << P_[p].sig[0], P_[p].sig[3], P_[p].sig[5], P_[p].sig[3], P_[p].sig[1], P_[p].sig[4], P_[p].sig[5], P_[p].sig[4], P_[p].sig[2];
  return s;
}

double MpmSolver::stableTimeStep() const { return maxSpeed_ > 0 ? cfg_.h / maxSpeed_ : kInf; }

// Stress update (Cauchy, stored on the particle), energy density per reference
// volume and the current dilatational wave speed (eq 27 with the current
// tangent shear modulus of the law).
MPM_CLONES Mat3 evaluateStress(const MpmMaterial& m, const Mat3& F, double massScaling, double& W, double& wave) {
  const auto& L = m.law;
  if (materials::lanes::hasLanes(L)) {
    // Fung-Demiray and neo-Hookean: the closed form of materials/stress_lanes.hpp
    // (seed 000 eqs 8-13), one point in all four lanes.
    A4 Fl[9], sl[6], W4, wave4;
    for (int c = 0; c < 9; ++c) Fl[c] = A4{} + F(c / 3, c % 3);
    materials::lanes::hyperelasticStress4(L, m.density * massScaling, Fl, sl, W4, wave4);
    W = W4[0];
    wave = wave4[0];
    Mat3 sigma;
    sigma << sl[0][0], sl[3][0], sl[5][0], sl[3][0], sl[1][0], sl[4][0], sl[5][0], sl[4][0], sl[2][0];
    return sigma;
  }
  const double J = F.determinant();
  Mat3 sigma;
  double muc = 0.0, K = 0.0;
  using materials::LawKind;
  if (L.kind == LawKind::Linear) {
    // St Venant-Kirchhoff, the library's "linear" law (materials/fast_stress.hpp).
    const materials::Lame l = materials::lame(L.E, L.nu);
    Mat3 S;
    materials::stVenantKirchhoffPk2(l, F, S, W);
    sigma = F * S * F.transpose() / J;
    muc = l.mu;
    K = l.lambda + 2.0 / 3.0 * l.mu;
  } else {
    materials::Stress3 s = materials::evaluate(L, F, false);
    sigma = s.sigma;
    W = s.energy;
    muc = L.initialShear();
    K = L.bulk;
  }
  const double rho = m.density * massScaling / J;
  wave = std::sqrt((K + 4.0 / 3.0 * muc) / rho);
  return sigma;
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

void MpmSolver::fail(std::size_t p, int cause) const {
  const Vec3 x = position(p);
  const std::string where =
      fmt::format("particle {} at ({:.4g}, {:.4g}, {:.4g}) mm, t = {:.6g} s, step {}", p, 1e3 * x.x(),
                  1e3 * x.y(), 1e3 * x.z(), time_, steps_);
  switch (cause) {
    case 1:
      throw SolverError("mpm: inverted or degenerate deformation gradient (det F <= 0) at " + where +
                        "; the step is too large for the deformation: lower model.mpm.time_step_factor or "
                        "the mass scaling, or refine the particles near the needle");
    case 2:
      throw SolverError("mpm: non-finite velocity or position at " + where +
                        "; the explicit step went unstable: lower model.mpm.time_step_factor or the mass "
                        "scaling, or check the material parameters");
    case 3:
    default:
      throw SolverError("mpm: a material point left the background grid: " + where +
                        "; enlarge the grid margin (model.mpm.margin) or constrain the block, or lower the "
                        "time step if the point flew off");
  }
}

// ---------------------------------------------------------------- grid buffers

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

// The points thread t of a team of T scatters in pass `colour` (0 .. 7, a
// barrier between two): a run of whole blocks of that colour, cut at the block
// boundaries nearest to equal point counts. One thread (no blocks): every
// point in creation order in pass 0.
std::pair<std::size_t, std::size_t> MpmSolver::colourShare(int t, int T, int colour) const {
  if (nthreads_ == 1) return t == 0 && colour == 0 ? std::pair<std::size_t, std::size_t>{0, size()}
                                                   : std::pair<std::size_t, std::size_t>{0, 0};
  const auto b0 = static_cast<std::ptrdiff_t>(colourStart_[static_cast<std::size_t>(colour)]),
             b1 = static_cast<std::ptrdiff_t>(colourStart_[static_cast<std::size_t>(colour) + 1]);
  const std::size_t p0 = blockStart_[static_cast<std::size_t>(b0)], p1 = blockStart_[static_cast<std::size_t>(b1)];
  const auto cut = [&](int u) -> std::size_t {
    if (u <= 0) return p0;
    if (u >= T) return p1;
    const std::size_t target = p0 + (p1 - p0) * static_cast<std::size_t>(u) / static_cast<std::size_t>(T);
    const auto first = blockStart_.begin() + b0, last = blockStart_.begin() + b1 + 1;
    const auto it = std::lower_bound(first, last, target);  // first boundary >= target (it != first: target >= p0)
    const std::size_t above = *it, below = *(it == first ? it : it - 1);
    return target - below <= above - target ? below : above;
  };
  return {cut(t), cut(t + 1)};
}

// Base nodes a point of listed block b may have at the start of a scatter:
// its block's, widened by one node on each side. A point with base node l
// reaches nodes l .. l + S - 1, so along an axis block n reaches nodes
// kBlock n - 1 .. kBlock n + kBlock + S - 1 and block n + 2 starts at
// kBlock n + 2 kBlock - 1: disjoint for kBlock >= S + 1 (S <= 3). Two blocks
// of one colour are two or more blocks apart along some axis.
void MpmSolver::blockBounds(std::size_t listed, int* lo, int* hi) const {
  std::uint32_t id = blockId_[listed];
  for (int a = 2; a >= 0; --a) {
    const int n = static_cast<int>(id % static_cast<std::uint32_t>(blocks_[a]));
    id /= static_cast<std::uint32_t>(blocks_[a]);
    lo[a] = blockOrigin_[a] + kBlock * n - 1;
    hi[a] = blockOrigin_[a] + kBlock * n + kBlock;
  }
}

// Stable counting sort of the points by colour, then block (base node of the
// support, clamped to the grid), creation order within a block; the blocks
// with points are listed. The passes over the points run on all threads
// (sortPointsByKey), the ranking of the blocks on one.
void MpmSolver::sortByBlock() {
  const std::size_t np = size();
  const double invh = 1.0 / cfg_.h;
  const double sh = cfg_.shape == Shape::Linear ? 0.0 : 0.5;
  const auto baseNode = [&](std::size_t p, int a) {
    return std::clamp(static_cast<int>(std::floor((P_[p].x[a] - cfg_.origin[a]) * invh - sh)), 0, nn_[a] - 1);
  };
  int lo0 = nn_[0] - 1, lo1 = nn_[1] - 1, lo2 = nn_[2] - 1;
#pragma omp parallel for schedule(static) num_threads(nthreads_) reduction(min : lo0, lo1, lo2)
  for (std::size_t p = 0; p < np; ++p) {
    lo0 = std::min(lo0, baseNode(p, 0));
    lo1 = std::min(lo1, baseNode(p, 1));
    lo2 = std::min(lo2, baseNode(p, 2));
  }
  const int lowest[3] = {lo0, lo1, lo2};
  for (int a = 0; a < 3; ++a) {
    blockOrigin_[a] = lowest[a];
    blocks_[a] = (nn_[a] - lowest[a] + kBlock - 1) / kBlock;
  }
  const auto nb1 = static_cast<std::size_t>(blocks_[1]), nb2 = static_cast<std::size_t>(blocks_[2]);
  const std::size_t nblocks = static_cast<std::size_t>(blocks_[0]) * nb1 * nb2;
  // rank of each grid block in colour-major order
  std::vector<std::uint32_t> rank(nblocks), idOfRank(nblocks);
  std::array<std::uint32_t, 9> firstOfColour{};
  std::uint32_t r = 0;
  for (std::size_t c = 0; c < 8; ++c) {
    firstOfColour[c] = r;
    for (std::size_t b = 0; b < nblocks; ++b) {
      const std::size_t bi = b / (nb1 * nb2), bj = b / nb2 % nb1, bk = b % nb2;
      if (((bi & 1) | (bj & 1) << 1 | (bk & 1) << 2) != c) continue;
      idOfRank[r] = static_cast<std::uint32_t>(b);
      rank[b] = r++;
    }
  }
  firstOfColour[8] = r;
  std::vector<std::uint32_t> key(np);
#pragma omp parallel for schedule(static) num_threads(nthreads_)
  for (std::size_t p = 0; p < np; ++p) {
    std::size_t b = 0;
    for (int a = 0; a < 3; ++a)
      b = b * static_cast<std::size_t>(blocks_[a]) + static_cast<std::size_t>((baseNode(p, a) - blockOrigin_[a]) / kBlock);
    key[p] = rank[b];
  }
  const std::vector<std::uint32_t> start = sortPointsByKey(key, nblocks);  // first entry of each block rank
  blockStart_.clear();
  blockId_.clear();
  for (std::size_t c = 0; c < 8; ++c) {
    colourStart_[c] = static_cast<std::uint32_t>(blockId_.size());
    for (std::uint32_t k = firstOfColour[c]; k < firstOfColour[c + 1]; ++k)
      if (start[k + 1] > start[k]) {
        blockId_.push_back(idOfRank[k]);
        blockStart_.push_back(start[k]);
      }
  }
  colourStart_[8] = static_cast<std::uint32_t>(blockId_.size());
  blockStart_.push_back(static_cast<std::uint32_t>(np));
  planned_ = true;
  ++sorts_;
}

// Stable counting sort of the points by key (< nkeys) into order_ on all
// threads: each thread counts its static share of the points, the offsets run
// key-major, then thread, so order_ is that of the serial stable sort. Returns
// the first entry of each key (nkeys + 1 entries).
std::vector<std::uint32_t> MpmSolver::sortPointsByKey(const std::vector<std::uint32_t>& key, std::size_t nkeys) {
  const std::size_t np = key.size();
  std::vector<std::uint32_t> count(static_cast<std::size_t>(nthreads_) * nkeys, 0);  // [thread][key]
  std::vector<std::uint32_t> start(nkeys + 1, 0);
  order_.resize(np);
#pragma omp parallel num_threads(nthreads_)
  {
    const auto t = static_cast<std::size_t>(threadId()), T = static_cast<std::size_t>(teamSize());
    const std::size_t p0 = np * t / T, p1 = np * (t + 1) / T;
    std::uint32_t* c = count.data() + t * nkeys;
    for (std::size_t p = p0; p < p1; ++p) ++c[key[p]];
#pragma omp barrier
#pragma omp single
    {
      std::uint32_t sum = 0;
      for (std::size_t k = 0; k < nkeys; ++k) {
        start[k] = sum;
        for (std::size_t u = 0; u < T; ++u) {
          const std::uint32_t n = count[u * nkeys + k];
          count[u * nkeys + k] = sum;  // thread u's next entry of key k
          sum += n;
        }
      }
      start[nkeys] = sum;
    }
    for (std::size_t p = p0; p < p1; ++p) order_[c[key[p]]++] = static_cast<std::uint32_t>(p);
  }
  return start;
}

// Before each step's scatter: sort the points by block when a point has left
// its block's bounds (blockBounds) or nothing is planned yet; one thread keeps
// the creation order.
void MpmSolver::planScatter() {
  if (nthreads_ == 1 || planned_) return;
  sortByBlock();
}

const char* MpmSolver::phaseName(int phase) {
  static constexpr std::array<const char*, kPhases> names = {
      "sort by block", "fork + zero grid",   "scatter (p2g)", "penalty contact", "grid row plan", "grid update",
      "rigid force sums", "contact: cut, CFEMP", "remap (g2p)", "remap update", "g2p + stress"};
  return phase >= 0 && phase < kPhases ? names[static_cast<std::size_t>(phase)] : "?";
}

std::vector<double> MpmSolver::threadBusy(Phase phase) const {
  const auto T = static_cast<std::size_t>(nthreads_);
  if (busy_.size() != kPhases * T) return std::vector<double>(T, 0.0);
  const auto first = busy_.begin() + static_cast<std::ptrdiff_t>(static_cast<std::size_t>(phase) * T);
  return {first, first + static_cast<std::ptrdiff_t>(T)};
}

// Thread t's work time in a particle pass (inside its parallel region: step()
// sized the slots, each thread adds to its own).
void MpmSolver::addBusy(Phase phase, int t, double seconds) {
  const std::size_t slot = static_cast<std::size_t>(phase) * static_cast<std::size_t>(nthreads_) + static_cast<std::size_t>(t);
  if (slot < busy_.size()) busy_[slot] += seconds;  // sized by step(); a pass outside it is not timed
}

MpmSolver::ScatterPlan MpmSolver::scatterPlan(int team) const {
  ScatterPlan plan;
  plan.sorts = sorts_;
  if (nthreads_ == 1 || team <= 1 || size() == 0 || !planned_) return plan;
  plan.colours = 0;
  plan.blocks = blockId_.size();
  std::vector<bool> busy(static_cast<std::size_t>(team), false);
  double critical = 0.0;
  for (int c = 0; c < 8; ++c) {
    if (colourStart_[static_cast<std::size_t>(c)] == colourStart_[static_cast<std::size_t>(c) + 1]) continue;
    ++plan.colours;
    std::size_t largest = 0;
    for (int t = 0; t < team; ++t) {
      const auto [q0, q1] = colourShare(t, team, c);
      largest = std::max(largest, q1 - q0);
      if (q1 > q0) busy[static_cast<std::size_t>(t)] = true;
    }
    critical += static_cast<double>(largest);
  }
  plan.busyThreads = static_cast<int>(std::count(busy.begin(), busy.end(), true));
  plan.imbalance = critical * team / static_cast<double>(size());
  return plan;
}

// ---------------------------------------------------------------- particle to grid (eqs 1-3)

namespace {
// Box dilation of the occupancy bits by `reach` cells along each axis: out =
// OR of in over the (2 reach + 1)^3 cells around; rows of rw = 2 W words (W
// per body, bit k), n0 x n1 rows; tmp is scratch of the same size.
void dilateCells(const std::uint64_t* in, std::uint64_t* out, std::uint64_t* tmp, std::size_t n0, std::size_t n1,
                 std::size_t W, std::size_t reach, std::uint64_t lastMask) {
  const std::size_t rw = 2 * W, rows = n0 * n1;
  // Along i (in -> out), then along j (out -> tmp): OR of the rows within reach.
  for (int d = 0; d < 2; ++d) {
    const std::uint64_t* src = d == 0 ? in : out;
    std::uint64_t* dst = d == 0 ? out : tmp;
    for (std::size_t row = 0; row < rows; ++row) {
      const std::size_t idx = d == 0 ? row / n1 : row % n1, n = d == 0 ? n0 : n1, stride = d == 0 ? n1 : 1;
      const std::size_t lo = idx >= reach ? idx - reach : 0, hi = std::min(n - 1, idx + reach);
      std::uint64_t* o = dst + row * rw;
      for (std::size_t w = 0; w < rw; ++w) o[w] = 0;
      for (std::size_t x = lo; x <= hi; ++x) {
        const std::uint64_t* r = src + (row + x * stride - idx * stride) * rw;
        for (std::size_t w = 0; w < rw; ++w) o[w] |= r[w];
      }
    }
  }
  // Along k (tmp -> out): bits shifted by -reach..reach within the row (across word edges).
  for (std::size_t row = 0; row < rows; ++row)
    for (std::size_t body = 0; body < 2; ++body) {
      const std::uint64_t* r = tmp + row * rw + body * W;
      std::uint64_t* o = out + row * rw + body * W;
      for (std::size_t w = 0; w < W; ++w) {
        const std::uint64_t x = r[w], prev = w > 0 ? r[w - 1] : 0, next = w + 1 < W ? r[w + 1] : 0;
        std::uint64_t v = x;
        for (unsigned s = 1; s <= reach; ++s) v |= (x << s) | (prev >> (64 - s)) | (x >> s) | (next << (64 - s));
        o[w] = w + 1 == W ? v & lastMask : v;
      }
    }
}
}  // namespace

// Two bodies: the bit of cell (i, j, k) in row (i, j) of body b is set in
// near_ when body b has a point within 3 cells (occupied cells dilated by 3
// along each axis). A node both bodies reach lies within 1.5 cells of a point
// of each, so the points that scatter to it are within 3 cells of the other
// body. near1_ (dilated by 1) marks the cells whose 27 neighbours hold a point
// of body b: the penalty contact's candidates (a pair touches at r < d <= h);
// the density law's kernel reaches H <= 3 h, dilated by its reach (1 to 3).
// A row is nearW_ 64-bit words per body (k = bit), so the dilation is shifts
// and ORs of words: serial, the arrays are small (n0 n1 rows of a few words).
// The occupancy comes from the previous step's g2pFinal, which marks the cell
// of each point at its new position; a pass over the points only after
// finalize or a failed step.
void MpmSolver::markNearBodies() {
  const std::size_t n0 = static_cast<std::size_t>(nn_[0]), n1 = static_cast<std::size_t>(nn_[1]),
                    n2 = static_cast<std::size_t>(nn_[2]);
  const std::size_t W = (n2 + 63) / 64, rw = 2 * W;  // words per row (both bodies)
  nearW_ = W;
  const std::size_t rows = n0 * n1, words = rows * rw;
  if (occ_.size() != words) {
    occ_.assign(words, 0);
    occFresh_ = false;
  }
  near1_.resize(words);
  near_.resize(words);
  nearTmp_.resize(words);
  if (!occFresh_) {
    const double invh = 1.0 / cfg_.h;
    const double ox = cfg_.origin.x(), oy = cfg_.origin.y(), oz = cfg_.origin.z();
    std::fill(occ_.begin(), occ_.end(), 0);
    for (std::size_t p = 0; p < size(); ++p) {
      const grid::Cell c = grid::cellAt((P_[p].x[0] - ox) * invh, (P_[p].x[1] - oy) * invh, (P_[p].x[2] - oz) * invh, n1);
      occ_[cellWord(c, body_[p], W)] |= cellBit(c);
    }
  }
  const std::uint64_t lastMask = n2 % 64 ? (std::uint64_t{1} << (n2 % 64)) - 1 : ~std::uint64_t{0};
  const std::size_t reach = penalty_ ? static_cast<std::size_t>(penalty_->reach()) : 1;  // 1 to 3 (density law)
  dilateCells(occ_.data(), near1_.data(), nearTmp_.data(), n0, n1, W, reach, lastMask);
  dilateCells(near1_.data(), near_.data(), nearTmp_.data(), n0, n1, W, 3 - reach, lastMask);  // 3 cells in all
  std::fill(occ_.begin(), occ_.end(), 0);  // g2pFinal marks the new positions
  occFresh_ = false;                       // until g2pFinal has marked them all
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
  const double gapReach = 2.0 * cfg_.h + cfg_.contactGap;
  const std::array<NeedleAxis, 8> ax = needleAxes(gapReach);
  Buf& B = buf_[0];
  double* __restrict rec = B.rec.data();
  double* __restrict grad = B.grad.data();  // two bodies
  std::uint32_t* __restrict nearCell = nearCell_.data();  // two bodies
  const bool centroid = !penalty_;  // the velocity contact's gap rule reads the mass-weighted positions
  const std::uint32_t* __restrict order = order_.data();
  const std::uint64_t* nearRows = near_.data();
  const std::uint64_t* near1Rows = near1_.data();
  const std::size_t nearW = nearW_;
  const bool gridClean = gridClean_;  // remapUpdate cleared the records it used
  gridClean_ = false;
  const int lastColour = lastScatterColour();
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
    const auto [q0, q1] = colourShare(t, T, colour);
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
        scatterCutPoint(p, Grad && needG, centroid);  // the support across the needle's cut left out
      else
        scatterPoint<S, Grad>(p, st, xp, needG, centroid, rec, grad, n1, n2);
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
    if (colour < lastColour && colourHasPoints(colour)) {
#pragma omp barrier
    }
    }
    addBusy(kScatter, t, worked);
    if (scattered) busy.fetch_add(1, std::memory_order_relaxed);
  }
  scatterThreads_ = busy.load();
  addPhase(kZeroGrid, start, cpuStart, zeroed, cpuZeroed);
  addPhase(kScatter, zeroed, cpuZeroed, wallSeconds(), cpuSeconds());
}

// p2g of point p over its support st (position xp): mass and momentum (eqs
// 1-2) and the internal force -V sigma : grad N into the records of its body;
// with needG (two bodies, the other one near) the gradient record too: mass
// gradient and mass-weighted position (its y, z lanes only for the centroid
// gap rule). Tensor-product form: for a node (i, j, k) w = wx_i wy_j wz_k and
// grad N = (dx_i wy_j wz_k, wx_i dy_j wz_k, wx_i wy_j dz_k), so every record
// entry is wz_k a_ij + dz_k b_ij with a, b formed once per (i, j); the k loop
// is a fixed-length vector update of one cache line.
template <int S, bool Grad>
[[gnu::always_inline]] inline void MpmSolver::scatterPoint(std::size_t p, const lanes::Stencil4<S>& st,
                                                           const double* xp, bool needG, bool centroid,
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
        // gradient record: mass gradient (3), mass-weighted position (3)
        const A4 a2 = {m * gxij[0], m * gyij[0], 0.0, wij[0] * m * xp[0]};
        const A4 b2 = {z0, z0, m * wij[0], z0};
        double* __restrict g = grad + 8 * node;
        for (int k = 0; k < S; ++k, r += NR, g += 8) {
          add(r, wz[k] * a0);
          add(r + 4, wz[k] * a1 + dz[k] * b1);
          add(g, wz[k] * a2 + dz[k] * b2);
        }
        if (centroid) {
          const A4 a3 = {wij[0] * m * xp[1], wij[0] * m * xp[2], z0, z0};
          g -= 8 * S;
          for (int k = 0; k < S; ++k, g += 8) add(g + 4, wz[k] * a3);
        }
      } else {
        for (int k = 0; k < S; ++k, r += NR) {
          add(r, wz[k] * a0);
          add(r + 4, wz[k] * a1 + dz[k] * b1);
        }
      }
    }
}

// ---------------------------------------------------------------- grid update and contact

namespace {

// Velocity-consistent contact of two deformable fields at a node (eqs 15-21):
// the normal velocities become equal, the tangential impulse is the sticking
// one limited by mu times the normal impulse.
inline void pairContact(double m0, double m1, double* v0, double* v1, const double* g0, const double* g1,
                        double mu, const double* x0, const double* x1, double gapLimit, const Vec3& xI,
                        const SurfaceFromCentroid* est, double h) {
  // g_b = sum_p m_p grad N_I(x_p) (gradient with respect to the particle
  // position) points out of body b at I. The normal averages the two unit
  // normals, n = g0/|g0| - g1/|g1| (from body 0 to body 1): the raw difference
  // g0 - g1 follows the heavier field, whose mass gradient at an edge or
  // corner node tilts towards its side face, and the tilt turns normal
  // approach into spurious tangential slip (friction work) and a wrong gap.
  const double a0 = std::sqrt(g0[0] * g0[0] + g0[1] * g0[1] + g0[2] * g0[2]);
  const double a1 = std::sqrt(g1[0] * g1[0] + g1[1] * g1[1] + g1[2] * g1[2]);
  if (!(a0 > 0) || !(a1 > 0)) return;
  Vec3 n(g0[0] / a0 - g1[0] / a1, g0[1] / a0 - g1[1] / a1, g0[2] / a0 - g1[2] / a1);
  const double nn = n.norm();
  if (!(nn > 0)) return;
  n /= nn;
  // Gap rule (no contact a cell early): the two surfaces estimated from the
  // field centroids at this node meet (Surface), or the centroids are closer
  // than those of two half-spaces touching at the node (Centroid).
  const Vec3 c0(x0[0] / m0, x0[1] / m0, x0[2] / m0), c1(x1[0] / m1, x1[1] / m1, x1[2] / m1);
  if (est) {
    // Surface rule: each field's surface from its centroid (surface_estimate.hpp).
    const double s0 = est->surface((c0 - xI).dot(n) / h);
    const double s1 = -est->surface(-(c1 - xI).dot(n) / h);
    if ((s1 - s0) * h > gapLimit) return;
  } else if ((c1 - c0).dot(n) > gapLimit) {
    return;
  }
  const Vec3 rel(v0[0] - v1[0], v0[1] - v1[1], v0[2] - v1[2]);
  const double vn = rel.dot(n);
  if (vn <= 0.0) return;  // separating (eq 14)
  const double mr = m0 * m1 / (m0 + m1);
  Vec3 dp = -mr * vn * n;                       // eq 18 times dt
  Vec3 rt = rel - vn * n;
  const double st = mr * rt.norm();             // eq 19 times dt
  const double lim = mu * mr * vn;              // eq 20 times dt
  if (st > 0) dp -= contact::coulombScale(st, lim) * mr * rt;  // eq 21
  for (int c = 0; c < 3; ++c) {
    v0[c] += dp[c] / m0;
    v1[c] -= dp[c] / m1;
  }
}

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
  addPhase(kGridPlan, start, cpuStart, wallSeconds(), cpuSeconds());
  // Node-wise work beyond eq 3 and the fixed components: rigid or velocity contact.
  const bool nodeWise = !rigids_.empty() || (cfg_.bodies == 2 && !penalty_);
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
  addPhase(kGridUpdate, planned, cpuPlanned, updated, cpuUpdated);
  addPhase(kRigidSums, updated, cpuUpdated, wallSeconds(), cpuSeconds());
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
  const double* dash = dashpot_.data();
  const std::uint8_t* fix = fixMask_.data();
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
  const double gap = cfg_.contactGap;
  const double mu = cfg_.friction;
  const double pairGap = pairGap_;
  const SurfaceFromCentroid* est = surfaceEst_ ? &*surfaceEst_ : nullptr;
  const std::size_t NR = static_cast<std::size_t>(nr_);
  const std::size_t n1 = static_cast<std::size_t>(nn_[1]), n2 = static_cast<std::size_t>(nn_[2]);
  const double* rec = G.rec.data();
  const std::uint8_t* fix = fixMask_.data();
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
    if (B == 2 && mb[0] > 0 && mb[1] > 0 && !penalty_)  // penalty: contact forces already in f_I
      pairContact(mb[0], mb[1], &vel_[8 * I], &vel_[8 * (nodes_ + I)], &G.grad[8 * I + kG],
                  &G.grad[8 * (nodes_ + I) + kG], mu, &G.grad[8 * I + kX], &G.grad[8 * (nodes_ + I) + kX],
                  pairGap, xI, est, cfg_.h);
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

// ---------------------------------------------------------------- CFEMP (eqs 22-24)

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
void MpmSolver::buildSurface(std::size_t r) {
  const RigidBody& rb = rigids_[r];
  if (rb.kind != RigidBody::Kind::Needle) throw Error("mpm: CFEMP contact needs a needle body");
  needle::NeedleShape sh;
  sh.radius = rb.radius;
  sh.length = rb.length;
  sh.tip = rb.tip == RigidBody::Tip::Bevel ? TipType::Bevel : rb.tip == RigidBody::Tip::Conical ? TipType::Conical : TipType::Blunt;
  sh.tipAngle = rb.tip == RigidBody::Tip::Blunt ? 0.5 * std::numbers::pi : rb.tipAngle;
  needle::NeedlePose pose;  // tip at 0, axis x, bevelSide y (sharp point at -R y)
  const double de = rb.elementSize > 0 ? rb.elementSize : dp_;
  const int nCirc = std::max(16, static_cast<int>(std::ceil(2 * std::numbers::pi * rb.radius / (0.25 * de))));
  const int nAxial = std::max(4, static_cast<int>(std::ceil(rb.length / de)));
  const needle::SurfaceMesh m = needle::needleSurface3D(sh, pose, nCirc, nAxial);
  Surface& S = surf_[r];
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
  S.reach = 0.5 * rb.elementSize + cfg_.contactGap + 0.5 * cfg_.h;  // gap rule + a margin for the motion
  S.cell = std::max(0.5 * rb.radius, 0.25 * cfg_.h);
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

// CFEMP pairs of rigid r (eq 22): the particles within the gap of the
// needle's nearest facet, with that facet's normal and part.
void MpmSolver::findSurfacePairs(std::size_t r) {
  const RigidBody& rb = rigids_[r];
  const Surface& Sf = surf_[r];
  const Vec3 e = rb.axis, ys = rb.bevelSide, zs = e.cross(ys);
  const Vec3 c0 = rb.axisPoint();  // the surface's origin (buildSurface)
  pairs_.clear();
  const double limit = 0.5 * rb.elementSize + cfg_.contactGap;  // eq 22: (d_e + d_p)/2
  for (std::size_t p = 0; p < size(); ++p) {
    const Vec3 q(P_[p].x[0] - c0.x(), P_[p].x[1] - c0.y(), P_[p].x[2] - c0.z());
    const Vec3 xl(q.dot(e), q.dot(ys), q.dot(zs));
    int c[3];
    bool in = true;
    for (int d = 0; d < 3 && in; ++d) {
      const double u = (xl[d] - Sf.lo[d]) / Sf.cell;
      in = u >= 0 && u < Sf.dim[d];
      c[d] = in ? static_cast<int>(u) : 0;
    }
    if (!in) continue;
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
    const bool outside = xl.y() * xl.y() + xl.z() * xl.z() >= rb.radius * rb.radius;
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
    if (bt < 0 || !(gap < limit)) continue;
    const Vec3& nl = Sf.n[static_cast<std::size_t>(bt)];
    const bool tipFacet = Sf.tip[static_cast<std::size_t>(bt)] != 0;
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
      if (st > 0) dp -= contact::coulombScale(st, -rb.friction * vn) * mp * rt;  // Coulomb, as eqs 19-21
      for (int a = 0; a < nn; ++a) {
        const double m = G.rec[NR * node[a] + kM];
        if (!(m > 0)) continue;
        const double f = wn[a] / m;
        const std::uint8_t mask = fixMask_[node[a] % nodes_];
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

// After the momentum remap of MUSL: the same contact (at the nodes found in
// the first update, with their normals) and boundary conditions on v*. Only
// the spans gridUpdate found: outside them the records and velocities are
// zero and no contact flag is set.
void MpmSolver::remapUpdate(bool clear) {
  const int B = cfg_.bodies;
  const std::size_t R = rigids_.size();
  Buf& G = buf_[0];
  const double mu = cfg_.friction;
  const double pairGap = pairGap_;
  const SurfaceFromCentroid* est = surfaceEst_ ? &*surfaceEst_ : nullptr;
  const std::size_t NR = static_cast<std::size_t>(nr_);
  const std::size_t n1 = static_cast<std::size_t>(nn_[1]), n2 = static_cast<std::size_t>(nn_[2]);
  const std::size_t rows = static_cast<std::size_t>(nn_[0]) * n1, UB = static_cast<std::size_t>(B);
  for (std::size_t q = 0; q < rows; ++q) {
    std::uint64_t w = 1;
    for (std::size_t b = 0; b < UB; ++b) w += rowSpan_[2 * (b * rows + q) + 1] - rowSpan_[2 * (b * rows + q)];
    rowWork_[q + 1] = rowWork_[q] + w;
  }
  const bool nodeWise = R > 0 || (B == 2 && !penalty_);
  double* rec = G.rec.data();
  double* vel = vel_.data();
  const std::uint8_t* fix = fixMask_.data();
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
      const int i = static_cast<int>(q / n1), j = static_cast<int>(q % n1);
      for (std::size_t k = h0; k < h1; ++k) {
        const std::size_t I = I0 + k;
        double mb[2] = {0, 0};
        for (std::size_t b = 0; b < UB; ++b) mb[b] = rec[NR * (b * nodes_ + I) + kM];
        if (B == 2 && mb[0] > 0 && mb[1] > 0 && !penalty_)  // penalty: the forces acted once, in f_I
          pairContact(mb[0], mb[1], &vel_[8 * I + 4], &vel_[8 * (nodes_ + I) + 4], &G.grad[8 * I + kG],
                      &G.grad[8 * (nodes_ + I) + kG], mu, &G.grad[8 * I + kX], &G.grad[8 * (nodes_ + I) + kX],
                      pairGap, cfg_.origin + cfg_.h * Vec3(i, j, static_cast<int>(k)), est, cfg_.h);
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

// ---------------------------------------------------------------- grid to particle (eq 4)

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
  const std::uint32_t* __restrict order = order_.data();
  const int lastColour = lastScatterColour();
  const std::uint32_t* cut = cutMask_.empty() ? nullptr : cutMask_.data();  // needle_cut.cpp
#pragma omp parallel num_threads(nthreads_)
  {
    const int T = teamSize(), t = threadId();
    double worked = 0;
    for (int colour = 0; colour <= lastColour; ++colour) {
    const double began = wallSeconds();
    const auto [q0, q1] = colourShare(t, T, colour);
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
    if (colour < lastColour && colourHasPoints(colour)) {
#pragma omp barrier
    }
    }
    addBusy(kRemap, t, worked);
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
  const std::uint32_t* __restrict order = order_.data();
  const bool blocked = nthreads_ > 1;
  bool strayed = false;
  const std::uint32_t* cut = cutMask_.empty() ? nullptr : cutMask_.data();  // needle_cut.cpp
  // Two bodies: mark each point's cell at its new position for the next
  // step's markNearBodies (it zeroed occ_), instead of a pass over the points there.
  std::uint64_t* occ = cfg_.bodies > 1 && !occ_.empty() ? occ_.data() : nullptr;
  const std::size_t occW = nearW_;
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
    block = static_cast<std::size_t>(std::upper_bound(blockStart_.begin(), blockStart_.end(), q0) - blockStart_.begin()) - 1;
    blockEnd = blockStart_[block + 1];
    blockBounds(block, lo, hi);
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
        while (qi >= blockStart_[block + 1]) ++block;
        blockEnd = blockStart_[block + 1];
        blockBounds(block, lo, hi);
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
  addBusy(kG2P, t, wallSeconds() - began);
  }
  if (strayed || bad.load()) planned_ = false;  // sort again before the next scatter
  if (bad.load()) fail(badP.load(), bad.load());
  occFresh_ = occ != nullptr;  // every point marked its cell
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
  if (occ) {  // as markNearBodies' own pass; threads meet at a row: atomic OR, skipped when set
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

// Anti-locking (F-bar, de Souza Neto et al. 1996, in the MPM form of cell
// averages): the volume change of every particle is replaced by the average
// over the particles in its grid cell, Jbar = sum V0 J / sum V0 (current over
// reference volume), and the stress is evaluated at Fbar = (Jbar / J)^(1/3) F.
// One volumetric constraint per cell instead of one per particle, so a nearly
// incompressible law (nu -> 0.5) no longer locks the 8 points of a cell; the
// deviatoric part of F is the particle's own. The stored F stays the true one.
void MpmSolver::fbarStress(double& eiOut, double& vmaxOut) {
  const std::size_t np = size();
  const double invh = 1.0 / cfg_.h;
  const double ox = cfg_.origin.x(), oy = cfg_.origin.y(), oz = cfg_.origin.z();
  const std::size_t n1 = static_cast<std::size_t>(nn_[1]), n2 = static_cast<std::size_t>(nn_[2]);
  cellOf_.resize(np);
  cellJ_.assign(2 * nodes_, 0.0);
  for (std::size_t p = 0; p < np; ++p) {  // serial: one multiply-add per particle
    const auto i = static_cast<std::size_t>((P_[p].x[0] - ox) * invh), j = static_cast<std::size_t>((P_[p].x[1] - oy) * invh),
               k = static_cast<std::size_t>((P_[p].x[2] - oz) * invh);
    const std::size_t c = (i * n1 + j) * n2 + k;  // cell by its lower node (inside: checked in g2pFinal)
    cellOf_[p] = static_cast<std::uint32_t>(c);
    cellJ_[2 * c] += P_[p].vol0 * defGrad(p).determinant();
    cellJ_[2 * c + 1] += P_[p].vol0;
  }
  double ei = 0.0, vmax = 0.0;
#pragma omp parallel for schedule(static) num_threads(nthreads_) reduction(+ : ei) reduction(max : vmax)
  for (std::size_t p = 0; p < np; ++p) {
    const std::size_t c = cellOf_[p];
    const Mat3 F = defGrad(p);
    const double Jbar = cellJ_[2 * c] / cellJ_[2 * c + 1];
    const Mat3 Fbar = std::cbrt(Jbar / F.determinant()) * F;
    double W, w;
    stress(p, Fbar, W, w);
    ei += P_[p].vol0 * W;
    vmax = std::max(vmax, w + std::sqrt(P_[p].v[0] * P_[p].v[0] + P_[p].v[1] * P_[p].v[1] + P_[p].v[2] * P_[p].v[2]));
  }
  eiOut += ei;
  vmaxOut = std::max(vmaxOut, vmax);
}

// ---------------------------------------------------------------- one step

StepReport MpmSolver::step() {
  if (!finalized_) finalize();
  const double dtcr = stableTimeStep();  // eq 25
  dt_ = cfg_.timeStepFactor * dtcr;      // eq 26
  if (cfg_.fixedTimeStep > 0) {
    if (cfg_.fixedTimeStep > dtcr)
      throw SolverError(fmt::format(
          "mpm: the fixed time step {:.3g} s exceeds the stable limit {:.3g} s (eq 25) at t = {:.6g} s; lower it "
          "or raise the mass scaling",
          cfg_.fixedTimeStep, dtcr, time_));
    dt_ = cfg_.fixedTimeStep;
  } else if (penalty_) {
    dt_ = std::min(dt_, penalty_->stepLimit(cfg_.penaltyStepFactor));  // two-body penalty contact (penalty_contact.hpp)
  }
  if (!(dt_ > 0) || !std::isfinite(dt_))
    throw SolverError("mpm: no valid time step (wave speed not finite); check the material parameters");
  if (device_) return deviceStep();  // GPU back-end (cuda/device_bridge.cpp)
  const bool lin = cfg_.shape == Shape::Linear;
  busy_.resize(kPhases * static_cast<std::size_t>(nthreads_), 0.0);
  double t0 = wallSeconds(), c0 = cpuSeconds();
  const auto lap = [&](Phase phase) {
    const double t1 = wallSeconds(), c1 = cpuSeconds();
    addPhase(phase, t0, c0, t1, c1);
    t0 = t1;
    c0 = c1;
  };
  planScatter();  // p2g clears the grid
  lap(kSort);
  planCut();      // the supports the needle's cut crosses (needle_cut.cpp)
  lap(kContact);
  if (cfg_.bodies > 1) {
    markNearBodies();
    if (lin) p2g<2, true>(); else p2g<3, true>();
  } else {
    if (lin) p2g<2, false>(); else p2g<3, false>();
  }
  t0 = wallSeconds(), c0 = cpuSeconds();  // p2g timed its parts
  if (penalty_) penaltyForces();  // two-body penalty contact: pair forces into f_I (penalty_contact.cpp)
  lap(kPenalty);
  gridUpdate();
  t0 = wallSeconds(), c0 = cpuSeconds();  // gridUpdate timed its parts
  const bool cfemp = std::any_of(rigids_.begin(), rigids_.end(), [](const RigidBody& r) { return r.surfaceContact; });
  if (cfemp) {
    if (lin) surfaceContact<2>(true); else surfaceContact<3>(true);
  }
  lap(kContact);
  if (cfg_.update == Update::MUSL) {
    if (lin) g2pRemap<2>(); else g2pRemap<3>();  // into the momentum lanes gridUpdate cleared
    lap(kRemap);
    remapUpdate(!cfemp);  // CFEMP reads the masses after it
    lap(kRemapUpdate);
    if (cfemp) {
      if (lin) surfaceContact<2>(false); else surfaceContact<3>(false);
    }
    lap(kContact);
  }
  double ek = 0, ei = 0, vmax = 0;
  if (cfg_.update == Update::USL) {
    if (lin) g2pFinal<2, true>(ek, ei, vmax); else g2pFinal<3, true>(ek, ei, vmax);
  } else {
    if (lin) g2pFinal<2, false>(ek, ei, vmax); else g2pFinal<3, false>(ek, ei, vmax);
  }
  lap(kG2P);
  maxSpeed_ = vmax;
  time_ += dt_;
  ++steps_;
  last_ = StepReport{dt_, ek, ei, vmax};
  if (penalty_) {
    penaltyEnergyAfterStep();
    last_.contact = penalty_->tally().energy;
    last_.penetration = penalty_->tally().penetration;
    last_.frictionWork = penalty_->frictionWork();
  }
  return last_;
}

}  // namespace needlesim::mpm
