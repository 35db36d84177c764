#include "needlesim/engines/realtime/tissue_integrators.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/SparseCholesky>
#include <algorithm>
#include <cmath>

#include "needlesim/core/error.hpp"
#include "needlesim/core/progress.hpp"
#include "needlesim/engines/realtime/sparse_cholesky.hpp"

namespace needlesim::realtime {

namespace {

// Per-step factors of QLV Prony viscoelasticity on the whole stiffness (materials/viscoelastic.hpp,
// seed 001 eqs 1-4): internal force K (g_inf u + sum g_i H_i) with
// H_i <- exp(-dt/tau_i) H_i + phi1(dt/tau_i) (u_new - u_old), so over a step the force is
// K (F u_new + sum g_i (decay_i H_i - phi_i u_old)), F = g_inf + sum g_i phi_i (Prony::stepFactor).
struct PronyStep {
  std::vector<double> g, decay, phi;
  double F = 1.0;
  void set(const materials::Prony& p, double dt) {
    g.clear(); decay.clear(); phi.clear();
    for (const auto& t : p.terms) {
      g.push_back(t.g);
      decay.push_back(std::exp(-dt / t.tau));
      phi.push_back(materials::phi1(dt / t.tau));
    }
    F = p.terms.empty() ? 1.0 : p.stepFactor(dt);
  }
  int terms() const { return static_cast<int>(g.size()); }
};

class DirectIntegrator final : public TissueIntegrator {
 public:
  DirectIntegrator(const Eigen::SparseMatrix<double>& K, const Eigen::SparseMatrix<double>& M, double alpha,
                   double beta, PathMap map, materials::Prony prony = {})
      : K_(K), M_(M), alpha_(alpha), beta_(beta), map_(std::move(map)), prony_(std::move(prony)) {
    const auto n = K.rows();
    u_.setZero(n); v_.setZero(n); a_.setZero(n);
    H_.assign(prony_.terms.size(), Eigen::VectorXd::Zero(n));
    hist_.setZero(n);
    b_.resize(n); u0_.resize(n); t1_.resize(n); t2_.resize(n); an_.resize(n);
  }
  Backend kind() const override { return Backend::Direct; }
  void prepare(const NewmarkCoefficients& c) override {
    c_ = c;
    ps_.set(prony_, c.dt);
    Eigen::SparseMatrix<double> A = K_ * (ps_.F + c.a1 * beta_) + M_ * (c.a0 + c.a1 * alpha_);
    {
      const BlockingCall call("realtime tissue: factorising the effective matrix");
      ldlt_.compute(A);
    }
    if (ldlt_.info() != Eigen::Success) throw SolverError("realtime tissue: the effective tissue matrix is not positive definite");
    invD_ = ldlt_.vectorD().cwiseInverse();  // vectorD() returns a copy: keep it out of step()
    const int P = map_.size();
    Z_.resize(K_.rows(), P);
    Eigen::VectorXd g(K_.rows());
    for (int k = 0; k < P; ++k) {
      throwIfStopRequested("realtime tissue: path flexibility");
      g.setZero();
      map_.scatterAdd(g, k, 1.0);
      Z_.col(k) = ldlt_.solve(g);
    }
    S_.resize(P, P);
    for (int k = 0; k < P; ++k)
      for (int l = 0; l < P; ++l) S_(l, k) = map_.gather(Z_.col(k), l);
    S_ = 0.5 * (S_ + S_.transpose()).eval();
  }
  const Eigen::MatrixXd& S() const override { return S_; }
  void predict(Eigen::VectorXd& u0P) override {
    // Right side of eq 3.4 with C = alpha M + beta K (eq 3.8).
    t1_ = (c_.a0 + alpha_ * c_.a1) * u_ + (c_.a2 + alpha_ * c_.a4) * v_ + (c_.a3 + alpha_ * c_.a5) * a_;
    t2_ = beta_ * (c_.a1 * u_ + c_.a4 * v_ + c_.a5 * a_);
    if (ps_.terms() > 0) {  // known part of the relaxing internal force
      hist_.setZero();
      for (int i = 0; i < ps_.terms(); ++i) hist_ += ps_.g[i] * (ps_.decay[i] * H_[i] - ps_.phi[i] * u_);
      t2_ -= hist_;
    }
    b_.noalias() = M_ * t1_;
    b_.noalias() += K_ * t2_;
    // ldlt_.solve(b_) without its temporary: P^T L^-T D^-1 L^-1 P b, in place (no allocation).
    an_.noalias() = ldlt_.permutationP() * b_;
    ldlt_.matrixL().solveInPlace(an_);
    an_.array() *= invD_.array();
    ldlt_.matrixU().solveInPlace(an_);
    u0_.noalias() = ldlt_.permutationPinv() * an_;
    for (int k = 0; k < map_.size(); ++k) u0P[k] = map_.gather(u0_, k);
  }
  void commit(const Eigen::VectorXd& f) override {
    for (int k = 0; k < f.size(); ++k)
      if (f[k] != 0.0) u0_.noalias() += f[k] * Z_.col(k);
    // eq 3.3 solved for the new acceleration, then eq 3.2.
    an_ = c_.a0 * (u0_ - u_) - c_.a2 * v_ - c_.a3 * a_;
    v_ += c_.dt * ((1.0 - gammaOf()) * a_ + gammaOf() * an_);
    for (int i = 0; i < ps_.terms(); ++i) H_[i] = ps_.decay[i] * H_[i] + ps_.phi[i] * (u0_ - u_);
    a_.swap(an_);
    u_.swap(u0_);
  }
  void movePathPoint(int i) override {
    Eigen::VectorXd g(K_.rows());
    for (int k = map_.comps() * i; k < map_.comps() * (i + 1); ++k) {
      g.setZero();
      map_.scatterAdd(g, k, 1.0);
      Z_.col(k) = ldlt_.solve(g);
    }
    for (int k = map_.comps() * i; k < map_.comps() * (i + 1); ++k)
      for (int l = 0; l < map_.size(); ++l) S_(k, l) = S_(l, k) = map_.gather(Z_.col(k), l);
  }
  void fullDisplacement(Eigen::VectorXd& u) const override { u = u_; }
  void fullVelocity(Eigen::VectorXd& v) const override { v = v_; }
  void saveDisplacement(DisplacementState& state) const override { state.coordinates = u_; }
  void displacementOf(const DisplacementState& state, Eigen::VectorXd& u) const override { u = state.coordinates; }
  double freeDisplacement(int k) const override { return u_[k]; }
  void setState(const Eigen::VectorXd& u, const Eigen::VectorXd& v, const Eigen::VectorXd& a) override {
    u_ = u; v_ = v; a_ = a;
    for (auto& h : H_) h = u;  // applied instantaneously: unrelaxed
  }

 private:
  double gammaOf() const { return c_.a1 / (c_.a2 == 0 ? 1.0 : c_.a2) ; }  // a1/a2 = gamma
  Eigen::SparseMatrix<double> K_, M_;
  double alpha_, beta_;
  PathMap map_;
  NewmarkCoefficients c_;
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt_;
  Eigen::MatrixXd Z_, S_;
  Eigen::VectorXd u_, v_, a_, b_, u0_, t1_, t2_, an_, hist_, invD_;
  materials::Prony prony_;
  PronyStep ps_;
  std::vector<Eigen::VectorXd> H_;
};

class ModalIntegrator final : public TissueIntegrator {
 public:
  ModalIntegrator(const Eigen::SparseMatrix<double>& K, const Eigen::SparseMatrix<double>& M, double alpha,
                  double beta, PathMap map, materials::Prony prony = {})
      : alpha_(alpha), beta_(beta), map_(std::move(map)), prony_(std::move(prony)) {
    const Eigen::MatrixXd Kd(K), Md(M);
    Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> es;
    {
      const BlockingCall call("realtime tissue: modes of the tissue");
      es.compute(Kd, Md);
    }
    if (es.info() != Eigen::Success) throw SolverError("realtime tissue: modal decomposition of the tissue failed");
    Phi_ = es.eigenvectors();  // M-orthonormal
    w2_ = es.eigenvalues().cwiseMax(0.0);
    const auto n = Phi_.cols();
    const int P = map_.size();
    PhiP_.resize(P, n);
    for (int k = 0; k < P; ++k)
      for (Eigen::Index m = 0; m < n; ++m) PhiP_(k, m) = map_.gather(Phi_.col(m), k);
    damp_ = (alpha_ + beta_ * w2_.array()).matrix();  // modal damping of eq 3.8
    q_.setZero(n); qd_.setZero(n); qdd_.setZero(n); q0_.resize(n); invA_.resize(n); g_.resize(n);
    h_.assign(prony_.terms.size(), Eigen::VectorXd::Zero(n));
  }
  Backend kind() const override { return Backend::Modal; }
  void prepare(const NewmarkCoefficients& c) override {
    c_ = c;
    ps_.set(prony_, c.dt);
    invA_ = (ps_.F * w2_.array() + c.a0 + c.a1 * damp_.array()).inverse().matrix();
    S_ = PhiP_ * invA_.asDiagonal() * PhiP_.transpose();
  }
  const Eigen::MatrixXd& S() const override { return S_; }
  void predict(Eigen::VectorXd& u0P) override {
    const auto& c = c_;
    q0_.array() = (c.a0 * q_.array() + c.a2 * qd_.array() + c.a3 * qdd_.array()) +
                  damp_.array() * (c.a1 * q_.array() + c.a4 * qd_.array() + c.a5 * qdd_.array());
    for (int i = 0; i < ps_.terms(); ++i)  // known part of the relaxing modal force
      q0_.array() -= w2_.array() * ps_.g[i] * (ps_.decay[i] * h_[i].array() - ps_.phi[i] * q_.array());
    q0_.array() *= invA_.array();
    u0P.noalias() = PhiP_ * q0_;
  }
  void commit(const Eigen::VectorXd& f) override {
    g_.setZero();
    for (int k = 0; k < f.size(); ++k)
      if (f[k] != 0.0) g_.noalias() += f[k] * PhiP_.row(k).transpose();
    const double gam = c_.a1 / c_.a2;
    q0_.array() += g_.array() * invA_.array();
    // New acceleration from eq 3.3, velocity from eq 3.2, mode by mode.
    g_.array() = c_.a0 * (q0_.array() - q_.array()) - c_.a2 * qd_.array() - c_.a3 * qdd_.array();
    qd_.array() += c_.dt * ((1.0 - gam) * qdd_.array() + gam * g_.array());
    for (int i = 0; i < ps_.terms(); ++i) h_[i] = ps_.decay[i] * h_[i] + ps_.phi[i] * (q0_ - q_);
    qdd_.swap(g_);
    q_.swap(q0_);
  }
  void movePathPoint(int i) override {
    for (int k = map_.comps() * i; k < map_.comps() * (i + 1); ++k)
      for (Eigen::Index m = 0; m < Phi_.cols(); ++m) PhiP_(k, m) = map_.gather(Phi_.col(m), k);
    for (int k = map_.comps() * i; k < map_.comps() * (i + 1); ++k) {
      S_.col(k) = PhiP_ * invA_.cwiseProduct(PhiP_.row(k).transpose());
      S_.row(k) = S_.col(k).transpose();
    }
  }
  void fullDisplacement(Eigen::VectorXd& u) const override { u.noalias() = Phi_ * q_; }
  void fullVelocity(Eigen::VectorXd& v) const override { v.noalias() = Phi_ * qd_; }
  void saveDisplacement(DisplacementState& state) const override { state.coordinates = q_; }
  void displacementOf(const DisplacementState& state, Eigen::VectorXd& u) const override {
    u.noalias() = Phi_ * state.coordinates;
  }
  double freeDisplacement(int k) const override { return Phi_.row(k).dot(q_); }
  void setState(const Eigen::VectorXd& u, const Eigen::VectorXd& v, const Eigen::VectorXd& a) override {
    // Phi^T M Phi = I, so q = Phi^-1 u; solve with the dense basis (setup only).
    const BlockingCall call("realtime tissue: initial modal state");
    const Eigen::PartialPivLU<Eigen::MatrixXd> lu(Phi_);
    q_ = lu.solve(u); qd_ = lu.solve(v); qdd_ = lu.solve(a);
    for (auto& h : h_) h = q_;
  }

 private:
  double alpha_, beta_;
  PathMap map_;
  NewmarkCoefficients c_;
  Eigen::MatrixXd Phi_;
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> PhiP_;
  Eigen::VectorXd w2_, damp_, q_, qd_, qdd_, q0_, invA_, g_;
  Eigen::MatrixXd S_;
  materials::Prony prony_;
  PronyStep ps_;
  std::vector<Eigen::VectorXd> h_;
};

// Truncated modal basis plus residual flexibility (docs/models/realtime2d.md, "reduced").
// The m lowest modes (shift-invert Lanczos on K, M-orthonormal) run Newmark exactly as in
// ModalIntegrator. Every other mode i has w_i above the cutoff where the Rayleigh term
// beta w_i^2 (eq 3.8) dwarfs 1/dt, so its inertia is negligible and it obeys
// (alpha + beta w_i^2) q' + w_i^2 q = phi_i^T f, i.e. beta g' + g = f for
// q_i = phi_i^T f-filtered / w_i^2 (alpha / w_i^2 << beta is dropped). Their sum on the
// path DOFs is R g with the residual flexibility R = G^T K^-1 G - Phi_P W^-2 Phi_P^T and
// one first-order filter g, advanced with the Newmark velocity rule (eq 3.2). Statics
// are exact (R + Phi_P W^-2 Phi_P^T = G^T K^-1 G); a step costs O((m + 2P) 2P).
// With Prony terms the filter relaxes too: beta g' + g_inf g + sum g_i H_i[g] = f.
class ReducedIntegrator final : public TissueIntegrator {
 public:
  ReducedIntegrator(const Eigen::SparseMatrix<double>& K, const Eigen::SparseMatrix<double>& M, double alpha,
                    double beta, PathMap map, double cutoff, int max_modes, materials::Prony prony = {})
      : K_(K), M_(M), alpha_(alpha), beta_(beta), map_(std::move(map)), prony_(std::move(prony)) {
    {
      const BlockingCall call("realtime tissue: factorising the stiffness");
      kf_.compute(K_);
    }
    if (kf_.info() != Eigen::Success) throw SolverError("realtime tissue: the tissue stiffness is singular (no supports?)");
    lanczos(cutoff, max_modes);
    const auto n = K_.rows();
    const int P = map_.size();
    const auto m = Phi_.cols();
    PhiP_.resize(P, m);
    for (int k = 0; k < P; ++k)
      for (Eigen::Index j = 0; j < m; ++j) PhiP_(k, j) = map_.gather(Phi_.col(j), k);
    // Static path flexibility G^T K^-1 G, minus the kept modes' share: one blocked solve
    // for all P path loads.
    throwIfStopRequested("realtime tissue: static path flexibility");
    Eigen::MatrixXd G = Eigen::MatrixXd::Zero(n, P);
    for (int k = 0; k < P; ++k) {
      Eigen::Ref<Eigen::VectorXd> g = G.col(k);
      map_.scatterAdd(g, k, 1.0);
    }
    {
      const BlockingCall call("realtime tissue: static path flexibility");
      Zs_ = kf_.solve(G);
    }
    R_.resize(P, P);
    for (int k = 0; k < P; ++k)
      for (int l = 0; l < P; ++l) R_(l, k) = map_.gather(Zs_.col(k), l);
    R_.noalias() -= PhiP_ * w2_.cwiseInverse().asDiagonal() * PhiP_.transpose();
    R_ = 0.5 * (R_ + R_.transpose()).eval();
    damp_ = (alpha_ + beta_ * w2_.array()).matrix();
    q_.setZero(m); qd_.setZero(m); qdd_.setZero(m); q0_.resize(m); invA_.resize(m); hq_.resize(m);
    gres_.setZero(P); gdot_.setZero(P); t_.resize(P); histr_.setZero(P);
    h_.assign(prony_.terms.size(), Eigen::VectorXd::Zero(m));
    Hr_.assign(prony_.terms.size(), Eigen::VectorXd::Zero(P));
  }
  Backend kind() const override { return Backend::Reduced; }
  int modes() const { return static_cast<int>(w2_.size()); }
  void prepare(const NewmarkCoefficients& c) override {
    c_ = c;
    gam_ = c.a1 / c.a2;
    ps_.set(prony_, c.dt);
    invA_ = (ps_.F * w2_.array() + c.a0 + c.a1 * damp_.array()).inverse().matrix();
    // beta g' + (g_inf g + sum g_i H_i) = f with g1 = g0 + dt((1 - gam) g0' + gam g1'):
    // g1 = t + cf1 f1 (t from the history in predict()); no creep (beta = 0): static.
    r_ = beta_ > 0.0 ? c.dt / beta_ : 0.0;
    cf1_ = beta_ > 0.0 ? gam_ * r_ / (1.0 + gam_ * r_ * ps_.F) : 1.0 / ps_.F;
    S_ = PhiP_ * invA_.asDiagonal() * PhiP_.transpose() + cf1_ * R_;
  }
  const Eigen::MatrixXd& S() const override { return S_; }
  void predict(Eigen::VectorXd& u0P) override {
    const auto& c = c_;
    q0_.array() = (c.a0 * q_.array() + c.a2 * qd_.array() + c.a3 * qdd_.array()) +
                  damp_.array() * (c.a1 * q_.array() + c.a4 * qd_.array() + c.a5 * qdd_.array());
    for (int i = 0; i < ps_.terms(); ++i)
      q0_.array() -= w2_.array() * ps_.g[i] * (ps_.decay[i] * h_[i].array() - ps_.phi[i] * q_.array());
    q0_.array() *= invA_.array();
    u0P.noalias() = PhiP_ * q0_;
    histr_.setZero();
    for (int i = 0; i < ps_.terms(); ++i) histr_ += ps_.g[i] * (ps_.decay[i] * Hr_[i] - ps_.phi[i] * gres_);
    if (beta_ > 0.0)
      t_ = (gres_ + c.dt * (1.0 - gam_) * gdot_ - gam_ * r_ * histr_) / (1.0 + gam_ * r_ * ps_.F);
    else
      t_ = -histr_ / ps_.F;
    u0P.noalias() += R_ * t_;
  }
  void commit(const Eigen::VectorXd& f) override {
    hq_.noalias() = PhiP_.transpose() * f;
    q0_.array() += hq_.array() * invA_.array();
    hq_.array() = c_.a0 * (q0_.array() - q_.array()) - c_.a2 * qd_.array() - c_.a3 * qdd_.array();
    qd_.array() += c_.dt * ((1.0 - gam_) * qdd_.array() + gam_ * hq_.array());
    for (int i = 0; i < ps_.terms(); ++i) h_[i] = ps_.decay[i] * h_[i] + ps_.phi[i] * (q0_ - q_);
    qdd_.swap(hq_);
    q_.swap(q0_);
    t_ += cf1_ * f;  // g1
    for (int i = 0; i < ps_.terms(); ++i) Hr_[i] = ps_.decay[i] * Hr_[i] + ps_.phi[i] * (t_ - gres_);
    if (beta_ > 0.0) gdot_ = (f - ps_.F * t_ - histr_) / beta_;
    gres_.swap(t_);
    resid_dirty_ = true;
  }
  // The point's rows of Phi_P, its static flexibility columns (one solve per load) and its rows
  // and columns of R and S; its filtered loads are zero (it took none), so the field is unchanged.
  void movePathPoint(int i) override {
    const int c = map_.comps(), k0 = c * i;
    Eigen::MatrixXd G = Eigen::MatrixXd::Zero(K_.rows(), c);
    for (int k = k0; k < k0 + c; ++k) {
      for (Eigen::Index m = 0; m < Phi_.cols(); ++m) PhiP_(k, m) = map_.gather(Phi_.col(m), k);
      Eigen::Ref<Eigen::VectorXd> g = G.col(k - k0);
      map_.scatterAdd(g, k, 1.0);
    }
    Zs_.middleCols(k0, c) = kf_.solve(G);
    for (int k = k0; k < k0 + c; ++k) {
      for (int l = 0; l < map_.size(); ++l) R_(l, k) = map_.gather(Zs_.col(k), l);
      R_.col(k).noalias() -= PhiP_ * w2_.cwiseInverse().cwiseProduct(PhiP_.row(k).transpose());
      R_.row(k) = R_.col(k).transpose();
    }
    for (int k = k0; k < k0 + c; ++k) {
      S_.col(k) = PhiP_ * invA_.cwiseProduct(PhiP_.row(k).transpose()) + cf1_ * R_.col(k);
      S_.row(k) = S_.col(k).transpose();
    }
    resid_dirty_ = true;
  }
  void fullDisplacement(Eigen::VectorXd& u) const override { fieldOf(q_, gres_, u); }
  void fullVelocity(Eigen::VectorXd& v) const override { fieldOf(qd_, gdot_, v); }
  void saveDisplacement(DisplacementState& state) const override {
    state.coordinates = q_;
    state.residual = gres_;
  }
  void displacementOf(const DisplacementState& state, Eigen::VectorXd& u) const override {
    fieldOf(state.coordinates, state.residual, u);
  }
  double freeDisplacement(int k) const override {
    if (resid_dirty_) { ures_ = residualField(gres_); resid_dirty_ = false; }
    return Phi_.row(k).dot(q_) + ures_[k];
  }
  void setState(const Eigen::VectorXd& u, const Eigen::VectorXd& v, const Eigen::VectorXd& a) override {
    q_ = Phi_.transpose() * (M_ * u);  // projection on the kept modes (Phi^T M Phi = I)
    qd_ = Phi_.transpose() * (M_ * v);
    qdd_ = Phi_.transpose() * (M_ * a);
    for (auto& h : h_) h = q_;
    gres_.setZero();
    gdot_.setZero();
    for (auto& h : Hr_) h.setZero();
    resid_dirty_ = true;
  }

 private:
  // Field of kept modal coordinates q and filtered path loads g (displacement: q, g;
  // velocity: q', g'): Phi q + (K^-1 G - Phi W^-2 Phi_P^T) g, with one product by Phi.
  void fieldOf(const Eigen::VectorXd& q, const Eigen::VectorXd& g, Eigen::VectorXd& out) const {
    const Eigen::VectorXd kept = q - w2_.cwiseInverse().asDiagonal() * (PhiP_.transpose() * g);
    out.noalias() = Phi_ * kept;
    out.noalias() += Zs_ * g;
  }
  // Field of the residual modes for filtered path loads g: (K^-1 G - Phi W^-2 Phi_P^T) g.
  Eigen::VectorXd residualField(const Eigen::VectorXd& g) const {
    Eigen::VectorXd r = Zs_ * g;
    r.noalias() -= Phi_ * (w2_.cwiseInverse().asDiagonal() * (PhiP_.transpose() * g));
    return r;
  }
  // Shift-invert Lanczos (operator K^-1 M, M inner product, full reorthogonalisation) for the
  // modes below `cutoff` (rad/s), at most max_modes; deterministic start vector.
  void lanczos(double cutoff, int max_modes) {
    const auto n = K_.rows();
    const int kmax = static_cast<int>(std::min<Eigen::Index>(n, std::max(3 * max_modes / 2, max_modes + 40)));
    Eigen::MatrixXd Q(n, kmax + 1);
    Eigen::VectorXd alpha(kmax), betas(kmax);
    Eigen::VectorXd q = Eigen::VectorXd::LinSpaced(n, 1.0, 2.0);
    for (Eigen::Index i = 0; i < n; i += 3) q[i] = -q[i];
    q /= std::sqrt(q.dot(M_ * q));
    Q.col(0) = q;
    Eigen::VectorXd r(n), Mr(n), Mq(n);
    int k = 0;
    auto done = [&](int steps) {  // enough converged Ritz values past the cutoff?
      Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(tridiag(alpha, betas, steps));
      int conv = 0;
      bool past = false;
      for (int i = steps - 1; i >= 0; --i) {  // largest theta = lowest w
        const double th = es.eigenvalues()[i];
        const double err = std::abs(betas[steps - 1] * es.eigenvectors()(steps - 1, i));
        if (!(err < 1e-9 * th)) break;
        ++conv;
        if (1.0 / th > cutoff * cutoff) { past = true; break; }
      }
      return past || conv >= max_modes;
    };
    for (; k < kmax; ++k) {
      throwIfStopRequested("realtime tissue: the lowest modes (Lanczos)");
      Mq.noalias() = M_ * Q.col(k);
      r = kf_.solve(Mq);
      alpha[k] = Q.col(k).dot(M_ * r);
      for (int pass = 0; pass < 2; ++pass) {  // full M-reorthogonalisation
        Mr = M_ * r;
        r.noalias() -= Q.leftCols(k + 1) * (Q.leftCols(k + 1).transpose() * Mr);
      }
      betas[k] = std::sqrt(std::max(r.dot(M_ * r), 0.0));
      if (betas[k] < 1e-14 * std::abs(alpha[k])) { ++k; break; }
      Q.col(k + 1) = r / betas[k];
      if ((k + 1) % 20 == 0 && done(k + 1)) { ++k; break; }
    }
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(tridiag(alpha, betas, k));
    std::vector<int> keep;
    for (int i = k - 1; i >= 0 && static_cast<int>(keep.size()) < max_modes; --i) {
      const double th = es.eigenvalues()[i];
      const double err = std::abs(betas[k - 1] * es.eigenvectors()(k - 1, i));
      if (!(th > 0.0) || !(err < 1e-8 * th)) break;  // only converged modes, lowest first
      keep.push_back(i);
      if (1.0 / th > cutoff * cutoff) break;
    }
    if (keep.empty()) throw SolverError("realtime tissue: the reduced basis (Lanczos) did not converge");
    Phi_.resize(n, static_cast<Eigen::Index>(keep.size()));
    w2_.resize(static_cast<Eigen::Index>(keep.size()));
    for (std::size_t j = 0; j < keep.size(); ++j) {
      Phi_.col(static_cast<Eigen::Index>(j)) = Q.leftCols(k) * es.eigenvectors().col(keep[j]);
      w2_[static_cast<Eigen::Index>(j)] = 1.0 / es.eigenvalues()[keep[j]];
    }
  }
  static Eigen::MatrixXd tridiag(const Eigen::VectorXd& a, const Eigen::VectorXd& b, int k) {
    Eigen::MatrixXd T = Eigen::MatrixXd::Zero(k, k);
    for (int i = 0; i < k; ++i) {
      T(i, i) = a[i];
      if (i + 1 < k) T(i, i + 1) = T(i + 1, i) = b[i];
    }
    return T;
  }

  Eigen::SparseMatrix<double> K_, M_;
  double alpha_, beta_;
  PathMap map_;
  NewmarkCoefficients c_;
  double gam_ = 0.5, r_ = 0, cf1_ = 1;
  materials::Prony prony_;
  PronyStep ps_;
  std::vector<Eigen::VectorXd> h_, Hr_;  // Prony histories: kept modes, residual filter
  SparseCholesky kf_;
  Eigen::MatrixXd Phi_, Zs_, R_, S_;
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> PhiP_;
  Eigen::VectorXd w2_, damp_, q_, qd_, qdd_, q0_, invA_, hq_, gres_, gdot_, t_, histr_;
  mutable Eigen::VectorXd ures_;
  mutable bool resid_dirty_ = true;
};

}  // namespace

std::unique_ptr<TissueIntegrator> makeDirectIntegrator(const Eigen::SparseMatrix<double>& K,
                                                       const Eigen::SparseMatrix<double>& M, double alpha,
                                                       double beta, PathMap map, materials::Prony prony) {
  return std::make_unique<DirectIntegrator>(K, M, alpha, beta, std::move(map), std::move(prony));
}
std::unique_ptr<TissueIntegrator> makeModalIntegrator(const Eigen::SparseMatrix<double>& K,
                                                      const Eigen::SparseMatrix<double>& M, double alpha,
                                                      double beta, PathMap map, materials::Prony prony) {
  return std::make_unique<ModalIntegrator>(K, M, alpha, beta, std::move(map), std::move(prony));
}
std::unique_ptr<TissueIntegrator> makeReducedIntegrator(const Eigen::SparseMatrix<double>& K,
                                                        const Eigen::SparseMatrix<double>& M, double alpha,
                                                        double beta, PathMap map, double cutoff, int max_modes,
                                                        materials::Prony prony) {
  return std::make_unique<ReducedIntegrator>(K, M, alpha, beta, std::move(map), cutoff, max_modes, std::move(prony));
}

}  // namespace needlesim::realtime
