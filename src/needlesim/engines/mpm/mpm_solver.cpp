// The MPM solver (mpm_solver.hpp): set-up, the checks of the initial state,
// and one explicit step composed of the passes in particle_to_grid.cpp,
// penalty_contact.cpp, grid_update.cpp, cfemp_contact.cpp, needle_cut.cpp and
// grid_to_particle.cpp; seed 000 eqs 1-4, 14-28 (docs/models/mpm.md).
#include "needlesim/engines/mpm/mpm_solver.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "needlesim/core/error.hpp"
#include "needlesim/engines/mpm/phase_clock.hpp"

#ifdef _OPENMP
#include <omp.h>
#endif

namespace needlesim::mpm {

namespace {
constexpr double kInf = std::numeric_limits<double>::infinity();
}  // namespace

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
  nearBodies_.setFresh(false);  // the first mark marks the cells from the positions
  vel_.assign(8 * B * nodes_, 0.0);
  gridClean_ = true;
  scatter_.reset(size(), nn_, nthreads_);
  scatterThreads_ = 1;
  active_.assign(R * nodes_, 0);
  rnormal_.assign(3 * R * nodes_, 0.0);
  rforce_.assign(R, RigidForce{});
  rigidGap_ = 0.5 * dp_;  // eq 22: the particles' half spacing
  surf_.assign(R, NeedleSurface{});
  for (std::size_t r = 0; r < R; ++r)
    if (rigids_[r].surfaceContact) {
      if (rigids_[r].kind != RigidBody::Kind::Needle) throw Error("mpm: CFEMP contact needs a needle body");
      surf_[r].build(rigids_[r], dp_, rigidGap_, cfg_.h);
    }
  setUpPairContact();
  bounds_.build(cfg_, nn_, mats_.empty() ? nullptr : &mats_[0]);
  checkInitialState();
  finalized_ = true;
}

// Pair penalty contact of two bodies (penalty_contact.hpp): stiffness kappa M d_p.
void MpmSolver::setUpPairContact() {
  const int B = cfg_.bodies;
  penalty_.reset();
  if (B > 1) {
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
                              "> {:.3g} mm); refine the particles",
                              2e3 * rmax, 1e3 * cfg_.h));
    penalty_.emplace(cfg_.penaltyFactor * M * dp_, std::move(radius), 0.5 * mmin, nthreads_);
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

Vec3 MpmSolver::nodePosition(std::size_t I) const {
  const std::size_t n12 = static_cast<std::size_t>(nn_[1]) * static_cast<std::size_t>(nn_[2]);
  const std::size_t n2 = static_cast<std::size_t>(nn_[2]);
  return cfg_.origin + cfg_.h * Vec3(static_cast<double>(I / n12), static_cast<double>((I / n2) % nn_[1]),
                                     static_cast<double>(I % n2));
}

Mat3 MpmSolver::cauchy(std::size_t p) const {
  Mat3 s;
  s << P_[p].sig[0], P_[p].sig[3], P_[p].sig[5], P_[p].sig[3], P_[p].sig[1], P_[p].sig[4], P_[p].sig[5], P_[p].sig[4], P_[p].sig[2];
  return s;
}

double MpmSolver::stableTimeStep() const { return maxSpeed_ > 0 ? cfg_.h / maxSpeed_ : std::numeric_limits<double>::infinity(); }

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

// The particles' positions as the scatter plan and the near-body cells read them.
PointPositions MpmSolver::positions() const {
  return {reinterpret_cast<const double*>(P_.data()), sizeof(Point) / sizeof(double), size(), cfg_.origin.data(),
          cfg_.h, cfg_.shape == Shape::Linear ? 0.0 : 0.5};
}

ScatterPlan MpmSolver::scatterPlan(int team) const { return scatter_.stats(team, size()); }

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
  clock_.sizeFor(nthreads_);
  double t0 = wallSeconds(), c0 = cpuSeconds();
  const auto lap = [&](Phase phase) {
    const double t1 = wallSeconds(), c1 = cpuSeconds();
    clock_.add(phase, t0, c0, t1, c1);
    t0 = t1;
    c0 = c1;
  };
  scatter_.plan(positions());  // p2g clears the grid
  lap(kSort);
  planCut();      // the supports the needle's cut crosses (needle_cut.cpp)
  lap(kContact);
  particleToGrid();
  t0 = wallSeconds(), c0 = cpuSeconds();  // p2g timed its parts
  if (penalty_) penaltyForces();  // two-body penalty contact: pair forces into f_I (penalty_contact.cpp)
  lap(kPenalty);
  gridUpdate();
  t0 = wallSeconds(), c0 = cpuSeconds();  // gridUpdate timed its parts
  const bool cfemp = std::any_of(rigids_.begin(), rigids_.end(), [](const RigidBody& r) { return r.surfaceContact; });
  if (cfemp) cfempContact(true);  // cfemp_contact.cpp
  lap(kContact);
  if (cfg_.update == Update::MUSL) {
    remapMomentum();  // into the momentum lanes gridUpdate cleared
    lap(kRemap);
    remapUpdate(!cfemp);  // CFEMP reads the masses after it
    lap(kRemapUpdate);
    if (cfemp) cfempContact(false);
    lap(kContact);
  }
  double ek = 0, ei = 0, vmax = 0;
  gridToParticle(ek, ei, vmax);
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
