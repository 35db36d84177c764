#include "needlesim/engines/realtime/tissue_dynamics.hpp"

#include <Eigen/SparseCholesky>
#include <fmt/format.h>
#include <algorithm>
#include <cmath>
#include <limits>

#include "needlesim/core/error.hpp"
#include "needlesim/core/progress.hpp"
#include "needlesim/engines/realtime/sparse_cholesky.hpp"
#include "needlesim/engines/realtime/tissue_integrators.hpp"

namespace needlesim::realtime {

TissueDynamics::TissueDynamics(std::string engine, const DynamicsSettings& cfg, const PathedSystem& sys, double dt)
    : engine_(std::move(engine)), cfg_(cfg), dim_(sys.dim), comps_(static_cast<int>(sys.dirs.cols())), dirs_(sys.dirs) {
  map_ = makeDofMap(static_cast<int>(sys.K.rows()), sys.held);
  K_ = restrictToFree(sys.K, map_);
  M_ = restrictToFree(sys.M, map_);
  for (int node : sys.path_nodes)
    for (int d = 0; d < dim_; ++d) pdof_.push_back(map_.free_of_dof[static_cast<std::size_t>(dim_ * node + d)]);
  pstart_ = sys.path_start;
  pweight_ = sys.path_weights;
  if (!pstart_.empty() && (pstart_.back() != static_cast<int>(sys.path_nodes.size()) || pweight_.size() != sys.path_nodes.size()))
    throw SolverError(engine_ + ": the path points' entries do not match their nodes");
  points_ = pstart_.empty() ? static_cast<int>(sys.path_nodes.size()) : static_cast<int>(pstart_.size()) - 1;
  makeIntegrator(dt);
  pu_.setZero(pathDofs()); pv_.setZero(pathDofs()); pa_.setZero(pathDofs()); u0P_.setZero(pathDofs());
  uP_.setZero(pathDofs());
  full_u_.setZero(sys.K.rows()); full_v_.setZero(sys.K.rows());
}

TissueDynamics::~TissueDynamics() = default;
TissueDynamics::TissueDynamics(TissueDynamics&&) noexcept = default;
TissueDynamics& TissueDynamics::operator=(TissueDynamics&&) noexcept = default;

void TissueDynamics::makeIntegrator(double dt) {
  const auto& cfg = cfg_;
  const PathMap pm = pathMap();
  materials::Prony prony{cfg.prony};
  prony.validate();
  Backend chosen = cfg.backend;
  if (chosen == Backend::Auto) chosen = map_.freeCount() <= cfg.modal_max_dofs ? Backend::Modal : Backend::Reduced;
  const double a = cfg.rayleigh_alpha, b = cfg.rayleigh_beta;
  if (chosen == Backend::Modal) {
    impl_ = makeModalIntegrator(K_, M_, a, b, pm, prony);
  } else if (chosen == Backend::Reduced) {
    // Keep the modes whose Rayleigh creep rate beta w^2 is below 20/dt (their inertia
    // matters within a step); all faster ones are residual (quasi-static creep).
    double cutoff = cfg.reduced_cutoff;
    if (!(cutoff > 0.0)) cutoff = b > 0.0 ? std::sqrt(20.0 / (b * dt)) : 2.0 / dt;
    impl_ = makeReducedIntegrator(K_, M_, a, b, pm, cutoff, cfg.reduced_max_modes, prony);
  } else {
    impl_ = makeDirectIntegrator(K_, M_, a, b, pm, prony);
  }
  // Conditionally stable Newmark: dt w_max <= 1 / sqrt(gamma/2 - beta) (undamped limit).
  dt_limit_ = std::numeric_limits<double>::infinity();
  if (cfg.newmark.beta < 0.5 * cfg.newmark.gamma && !cfg.newmark.unconditionallyStable())
    dt_limit_ = 1.0 / (std::sqrt(0.5 * cfg.newmark.gamma - cfg.newmark.beta) * highestFrequency());
  checkStable(dt);
  nm_ = NewmarkCoefficients(cfg.newmark, dt);
  impl_->prepare(nm_);
}

PathMap TissueDynamics::pathMap() const {
  return pstart_.empty() ? PathMap{&pdof_, dim_, dirs_} : PathMap{&pdof_, dim_, dirs_, &pstart_, &pweight_};
}

Backend TissueDynamics::backend() const { return impl_->kind(); }

void TissueDynamics::movePathPoint(int i, const std::vector<int>& nodes, const std::vector<double>& weights) {
  if (pstart_.empty() || i < 0 || i >= points_ || nodes.size() != weights.size() || nodes.empty())
    throw SolverError(engine_ + ": a path point can be moved only onto weighted mesh nodes");
  const auto b = static_cast<std::ptrdiff_t>(pstart_[static_cast<std::size_t>(i)]);
  const auto e = static_cast<std::ptrdiff_t>(pstart_[static_cast<std::size_t>(i) + 1]);
  std::vector<int> dofs;
  for (int node : nodes)
    for (int d = 0; d < dim_; ++d) dofs.push_back(map_.free_of_dof[static_cast<std::size_t>(dim_ * node + d)]);
  pdof_.erase(pdof_.begin() + dim_ * b, pdof_.begin() + dim_ * e);
  pdof_.insert(pdof_.begin() + dim_ * b, dofs.begin(), dofs.end());
  pweight_.erase(pweight_.begin() + b, pweight_.begin() + e);
  pweight_.insert(pweight_.begin() + b, weights.begin(), weights.end());
  const int shift = static_cast<int>(nodes.size()) - static_cast<int>(e - b);
  for (std::size_t j = static_cast<std::size_t>(i) + 1; j < pstart_.size(); ++j) pstart_[j] += shift;
  impl_->movePathPoint(i);
  Eigen::VectorXd uf, vf;
  impl_->fullDisplacement(uf);
  impl_->fullVelocity(vf);
  const PathMap pm = pathMap();
  for (int k = comps_ * i; k < comps_ * (i + 1); ++k) {
    pu_[k] = pm.gather(uf, k); pv_[k] = pm.gather(vf, k); pa_[k] = 0.0;
  }
}

void TissueDynamics::checkStable(double dt) const {
  if (dt > dt_limit_)
    throw SolverError(fmt::format(
        "{}: time step {:g} s exceeds the stability limit {:g} s of Newmark gamma = {:g}, beta = {:g} "
        "for this mesh (highest frequency {:.4g} rad/s; limit dt w_max <= 1/sqrt(gamma/2 - beta)). Use a "
        "smaller time step, a coarser mesh, or gamma = 0.5, beta = 0.25 (unconditionally stable)",
        engine_, dt, dt_limit_, cfg_.newmark.gamma, cfg_.newmark.beta,
        1.0 / (std::sqrt(0.5 * cfg_.newmark.gamma - cfg_.newmark.beta) * dt_limit_)));
}

void TissueDynamics::setTimeStep(double dt) {
  if (dt == nm_.dt) return;
  checkStable(dt);
  nm_ = NewmarkCoefficients(cfg_.newmark, dt);
  impl_->prepare(nm_);
}
const Eigen::MatrixXd& TissueDynamics::pathCompliance() const { return impl_->S(); }
void TissueDynamics::predict() { impl_->predict(u0P_); }

void TissueDynamics::commit(const Eigen::VectorXd& f) {
  impl_->commit(f);
  // Path state: u = u0 + S f exactly; v and a by eqs 3.2-3.3 on those DOFs.
  // u0 + S f a column of S at a time (each entry sums in the same order as row by row).
  const auto& S = impl_->S();
  uP_ = u0P_;
  for (int l = 0; l < pathDofs(); ++l)
    if (f[l] != 0.0) uP_.noalias() += f[l] * S.col(l);
  for (int k = 0; k < pathDofs(); ++k) {
    const double u = uP_[k];
    const double an = nm_.acceleration(u, pu_[k], pv_[k], pa_[k]);
    pv_[k] = nm_.velocity(pv_[k], pa_[k], an);
    pa_[k] = an;
    pu_[k] = u;
  }
  displacementStale_ = velocityStale_ = true;
}

// Free-DOF values into a full nodal vector; held DOFs keep what `full` has (0).
void TissueDynamics::scatterFree(const Eigen::VectorXd& free, Eigen::VectorXd& full) const {
  for (int k = 0; k < map_.freeCount(); ++k) full[map_.dof_of_free[static_cast<std::size_t>(k)]] = free[k];
}

void TissueDynamics::refreshDisplacement() const {
  if (!displacementStale_) return;
  impl_->fullDisplacement(fu_);
  scatterFree(fu_, full_u_);
  displacementStale_ = false;
}
void TissueDynamics::refreshVelocity() const {
  if (!velocityStale_) return;
  impl_->fullVelocity(fv_);
  scatterFree(fv_, full_v_);
  velocityStale_ = false;
}
const Eigen::VectorXd& TissueDynamics::displacement() const { refreshDisplacement(); return full_u_; }
const Eigen::VectorXd& TissueDynamics::velocity() const { refreshVelocity(); return full_v_; }

void TissueDynamics::saveDisplacement(DisplacementState& state) const { impl_->saveDisplacement(state); }

void TissueDynamics::displacementFrom(const DisplacementState& state, Eigen::VectorXd& full) const {
  Eigen::VectorXd free;
  impl_->displacementOf(state, free);
  full.setZero(static_cast<Eigen::Index>(map_.free_of_dof.size()));
  scatterFree(free, full);
}

double TissueDynamics::dofDisplacement(int dof) const {
  const int k = map_.free_of_dof[static_cast<std::size_t>(dof)];
  if (k < 0) return 0.0;
  return displacementStale_ ? impl_->freeDisplacement(k) : full_u_[dof];
}

double TissueDynamics::kineticEnergy() const {
  refreshVelocity();
  return 0.5 * fv_.dot(M_ * fv_);
}
double TissueDynamics::strainEnergy() const {
  refreshDisplacement();
  return 0.5 * fu_.dot(K_ * fu_);
}

void TissueDynamics::setState(const Eigen::VectorXd& u, const Eigen::VectorXd& v) {
  const int n = map_.freeCount();
  Eigen::VectorXd uf(n), vf(n);
  for (int k = 0; k < n; ++k) {
    uf[k] = u[map_.dof_of_free[static_cast<std::size_t>(k)]];
    vf[k] = v[map_.dof_of_free[static_cast<std::size_t>(k)]];
  }
  const Eigen::SparseMatrix<double> C = cfg_.rayleigh_alpha * M_ + cfg_.rayleigh_beta * K_;
  SparseCholesky mf;
  {
    const BlockingCall call(engine_ + ": factorising the mass matrix");
    mf.compute(M_);
  }
  const Eigen::VectorXd rhs = -(C * vf + K_ * uf);
  const Eigen::VectorXd af = mf.solve(rhs);
  impl_->setState(uf, vf, af);
  const PathMap pm = pathMap();
  for (int k = 0; k < pathDofs(); ++k) {
    pu_[k] = pm.gather(uf, k); pv_[k] = pm.gather(vf, k); pa_[k] = pm.gather(af, k);
  }
  displacementStale_ = velocityStale_ = true;
}

double TissueDynamics::highestFrequency() const {
  // Power iteration on M^-1 K (Rayleigh quotient), deterministic start vector.
  SparseCholesky mf;
  {
    const BlockingCall call(engine_ + ": factorising the mass matrix");
    mf.compute(M_);
  }
  Eigen::VectorXd x = Eigen::VectorXd::LinSpaced(M_.rows(), 1.0, 2.0);
  for (Eigen::Index i = 0; i < x.size(); i += 2) x[i] = -x[i];
  double lam = 0.0;
  for (int it = 0; it < 300; ++it) {
    throwIfStopRequested(engine_ + ": the highest frequency of the tissue");
    const Eigen::VectorXd Kx = K_ * x;
    Eigen::VectorXd y = mf.solve(Kx);
    const double nl = x.dot(K_ * x) / x.dot(M_ * x);
    x = y / y.norm();
    if (it > 10 && std::abs(nl - lam) < 1e-6 * nl) { lam = nl; break; }
    lam = nl;
  }
  return std::sqrt(std::max(lam, 0.0));
}

Eigen::VectorXd TissueDynamics::staticSolve(const Eigen::VectorXd& f) const {
  const int n = map_.freeCount();
  Eigen::VectorXd ff(n);
  for (int k = 0; k < n; ++k) ff[k] = f[map_.dof_of_free[static_cast<std::size_t>(k)]];
  SparseCholesky kf;
  {
    const BlockingCall call(engine_ + ": factorising the stiffness");
    kf.compute(K_);
  }
  if (kf.info() != Eigen::Success) throw SolverError(engine_ + ": the tissue stiffness is singular (no supports?)");
  const Eigen::VectorXd uf = kf.solve(ff);
  Eigen::VectorXd u = Eigen::VectorXd::Zero(f.size());
  for (int k = 0; k < n; ++k) u[map_.dof_of_free[static_cast<std::size_t>(k)]] = uf[k];
  return u;
}

}  // namespace needlesim::realtime
