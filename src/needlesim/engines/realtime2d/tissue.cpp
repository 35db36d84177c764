#include "needlesim/engines/realtime2d/tissue.hpp"

#include <Eigen/Eigenvalues>
#include <fmt/format.h>
#include <limits>
#include <Eigen/SparseCholesky>
#include <algorithm>
#include <cmath>
#include <string>

#include "needlesim/core/error.hpp"
#include "needlesim/materials/viscoelastic.hpp"

namespace needlesim::realtime2d {

NewmarkCoefficients::NewmarkCoefficients(const NewmarkParams& p, double h) {
  if (!(h > 0.0)) throw SolverError("realtime2d: the time step must be > 0");
  if (!(p.beta > 0.0) || !(p.gamma > 0.0)) throw SolverError("realtime2d: Newmark gamma and beta must be > 0");
  dt = h;
  a0 = 1.0 / (p.beta * h * h);
  a1 = p.gamma / (p.beta * h);
  a2 = 1.0 / (p.beta * h);
  a3 = 1.0 / (2.0 * p.beta) - 1.0;
  a4 = p.gamma / p.beta - 1.0;
  a5 = 0.5 * h * (p.gamma / p.beta - 2.0);
}

// ---------------------------------------------------------------------------
struct PathMap {  // the path loads' placement on the free DOFs
  const std::vector<std::array<int, 2>>* pdof;
  Eigen::Vector2d t, n;
  // Direction (x, y) of path load k (k = 2 i + 0: axial t, + 1: lateral n).
  const Eigen::Vector2d& dir(int k) const { return (k % 2 == 0) ? t : n; }
  template <class Vec>
  double gather(const Vec& u, int k) const {
    const auto& d = (*pdof)[static_cast<std::size_t>(k / 2)];
    const auto& e = dir(k);
    double s = 0.0;
    if (d[0] >= 0) s += e.x() * u[d[0]];
    if (d[1] >= 0) s += e.y() * u[d[1]];
    return s;
  }
  template <class Vec>
  void scatterAdd(Vec& u, int k, double f) const {
    const auto& d = (*pdof)[static_cast<std::size_t>(k / 2)];
    const auto& e = dir(k);
    if (d[0] >= 0) u[d[0]] += e.x() * f;
    if (d[1] >= 0) u[d[1]] += e.y() * f;
  }
  int size() const { return 2 * static_cast<int>(pdof->size()); }
};

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

class TissueIntegrator {
 public:
  virtual ~TissueIntegrator() = default;
  virtual Backend kind() const = 0;
  virtual void prepare(const NewmarkCoefficients& c) = 0;
  virtual const Eigen::MatrixXd& S() const = 0;
  virtual void predict(Eigen::VectorXd& u0P) = 0;
  virtual void commit(const Eigen::VectorXd& f) = 0;
  virtual void fullState(Eigen::VectorXd& u, Eigen::VectorXd& v) const = 0;  // free DOFs
  virtual void setState(const Eigen::VectorXd& u, const Eigen::VectorXd& v, const Eigen::VectorXd& a) = 0;
  virtual double freeDisplacement(int k) const = 0;  // one free DOF of u
};

namespace {

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
    ldlt_.compute(A);
    if (ldlt_.info() != Eigen::Success) throw SolverError("realtime2d: the effective tissue matrix is not positive definite");
    invD_ = ldlt_.vectorD().cwiseInverse();  // vectorD() returns a copy: keep it out of step()
    const int P = map_.size();
    Z_.resize(K_.rows(), P);
    Eigen::VectorXd g(K_.rows());
    for (int k = 0; k < P; ++k) {
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
  void fullState(Eigen::VectorXd& u, Eigen::VectorXd& v) const override { u = u_; v = v_; }
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
    Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> es(Kd, Md);
    if (es.info() != Eigen::Success) throw SolverError("realtime2d: modal decomposition of the tissue failed");
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
  void fullState(Eigen::VectorXd& u, Eigen::VectorXd& v) const override {
    u.noalias() = Phi_ * q_;
    v.noalias() = Phi_ * qd_;
  }
  double freeDisplacement(int k) const override { return Phi_.row(k).dot(q_); }
  void setState(const Eigen::VectorXd& u, const Eigen::VectorXd& v, const Eigen::VectorXd& a) override {
    // Phi^T M Phi = I, so q = Phi^-1 u; solve with the dense basis (setup only).
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
    kf_.compute(K_);
    if (kf_.info() != Eigen::Success) throw SolverError("realtime2d: the tissue stiffness is singular (no supports?)");
    lanczos(cutoff, max_modes);
    const auto n = K_.rows();
    const int P = map_.size();
    const auto m = Phi_.cols();
    PhiP_.resize(P, m);
    for (int k = 0; k < P; ++k)
      for (Eigen::Index j = 0; j < m; ++j) PhiP_(k, j) = map_.gather(Phi_.col(j), k);
    // Static path flexibility G^T K^-1 G, minus the kept modes' share.
    Zs_.resize(n, P);
    Eigen::VectorXd g(n);
    for (int k = 0; k < P; ++k) {
      g.setZero();
      map_.scatterAdd(g, k, 1.0);
      Zs_.col(k) = kf_.solve(g);
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
  void fullState(Eigen::VectorXd& u, Eigen::VectorXd& v) const override {
    u.noalias() = Phi_ * q_;
    u += residualField(gres_);
    v.noalias() = Phi_ * qd_;
    v += residualField(gdot_);
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
    Eigen::VectorXd r(n), Mr(n);
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
      r = kf_.solve(M_ * Q.col(k));
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
    if (keep.empty()) throw SolverError("realtime2d: the reduced basis (Lanczos) did not converge");
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
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> kf_;
  Eigen::MatrixXd Phi_, Zs_, R_, S_;
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> PhiP_;
  Eigen::VectorXd w2_, damp_, q_, qd_, qdd_, q0_, invA_, hq_, gres_, gdot_, t_, histr_;
  mutable Eigen::VectorXd ures_;
  mutable bool resid_dirty_ = true;
};

}  // namespace

namespace {
Eigen::Vector2d elementCentre(const Mesh& mesh, int e) {
  Eigen::Vector2d c = Eigen::Vector2d::Zero();
  for (int a = 0; a < 4; ++a) c += 0.25 * mesh.nodes.col(mesh.quads(a, e));
  return c;
}

// Winkler springs on the held sides: k times each node's tributary boundary length times t.
Eigen::SparseMatrix<double> boundarySprings(const Mesh& mesh, double k, double thickness) {
  std::vector<Eigen::Triplet<double>> t;
  auto add = [&](int node, double len) {
    t.emplace_back(2 * node, 2 * node, k * len * thickness);
    t.emplace_back(2 * node + 1, 2 * node + 1, k * len * thickness);
  };
  auto trib = [](const std::vector<double>& c, int i) {
    const int n = static_cast<int>(c.size());
    double l = 0.0;
    if (i > 0) l += 0.5 * (c[static_cast<std::size_t>(i)] - c[static_cast<std::size_t>(i - 1)]);
    if (i + 1 < n) l += 0.5 * (c[static_cast<std::size_t>(i + 1)] - c[static_cast<std::size_t>(i)]);
    return l;
  };
  for (int i = 0; i < mesh.nx; ++i) {
    add(mesh.node(i, 0), trib(mesh.xs, i));
    add(mesh.node(i, mesh.ny - 1), trib(mesh.xs, i));
  }
  for (int j = 0; j < mesh.ny; ++j) add(mesh.node(mesh.nx - 1, j), trib(mesh.ys, j));
  const int N = 2 * mesh.nodeCount();
  Eigen::SparseMatrix<double> Ks(N, N);
  Ks.setFromTriplets(t.begin(), t.end());
  return Ks;
}
}  // namespace

// ---------------------------------------------------------------------------
Tissue::Tissue(const TissueConfig& cfg, const Eigen::Vector2d& entry, const Eigen::Vector2d& axis, double dt)
    : mesh_(generateMesh(cfg.mesh)), cfg_(cfg) {
  t_ = axis.normalized();
  n_ = Eigen::Vector2d(-t_.y(), t_.x());
  assignMaterials(entry);
  const std::vector<bool> onSides = nodesOnHeldSides(mesh_);
  assembleSupported(onSides);
  pickPath(entry, onSides);
  makeIntegrator(dt);
  const int N = mesh_.nodeCount();
  pu_.setZero(pathDofs()); pv_.setZero(pathDofs()); pa_.setZero(pathDofs());
  full_u_.setZero(2 * N); full_v_.setZero(2 * N);
  u0P_.setZero(pathDofs());
}

// Element materials: by the layer of the element centre, then the material regions
// (inclusions) holding the centre, then the stiffening around the needle path.
void Tissue::assignMaterials(const Eigen::Vector2d& entry) {
  const auto& cfg = cfg_;
  elem_mat_.assign(static_cast<std::size_t>(mesh_.elementCount()), cfg.material);
  std::vector<std::vector<bool>> inRegion(cfg.regions.size(), std::vector<bool>(static_cast<std::size_t>(mesh_.nodeCount()), false));
  for (int e = 0; e < mesh_.elementCount(); ++e) {
    const Eigen::Vector2d c = elementCentre(mesh_, e);
    ElasticMaterial& m = elem_mat_[static_cast<std::size_t>(e)];
    if (!cfg.layers.empty()) {
      std::size_t L = 0;
      while (L + 1 < cfg.layers.size() && c.x() > cfg.layers[L].first) ++L;
      m = cfg.layers[L].second;
    }
    for (std::size_t r = 0; r < cfg.regions.size(); ++r) {
      if ((c - cfg.regions[r].centre).norm() > cfg.regions[r].radius) continue;
      m = cfg.regions[r].material;
      for (int a = 0; a < 4; ++a) inRegion[r][static_cast<std::size_t>(mesh_.quads(a, e))] = true;
    }
    m.thickness = cfg.material.thickness;
    m.plane_strain = cfg.material.plane_strain;
  }
  region_nodes_.assign(cfg.regions.size(), {});
  for (std::size_t r = 0; r < cfg.regions.size(); ++r) {
    for (int n = 0; n < mesh_.nodeCount(); ++n)
      if (inRegion[r][static_cast<std::size_t>(n)]) region_nodes_[r].push_back(n);
    if (region_nodes_[r].empty())
      throw SolverError(fmt::format("realtime2d: material region {} (radius {:g} mm) holds no element centre of the "
                                    "mesh; refine the mesh or enlarge the region",
                                    r, cfg.regions[r].radius * 1e3));
  }
  if (cfg.stiffening_factor != 1.0 && cfg.stiffening_radius > 0.0) {
    if (!(cfg.stiffening_factor > 0.0)) throw SolverError("realtime2d: the stiffening factor must be > 0");
    // Seed 003 section 3.5 item 4: the tissue around the needle path is stiffer (the shaft
    // confines it), so nodes next to the shaft are dragged less and the needle slips past.
    for (int e = 0; e < mesh_.elementCount(); ++e)
      if (std::abs((elementCentre(mesh_, e) - entry).dot(n_)) <= cfg.stiffening_radius)
        elem_mat_[static_cast<std::size_t>(e)].E *= cfg.stiffening_factor;
  }
}

// K and M on the free DOFs: every side but the entry face held (seed 003 section 3.5
// item 3), or Winkler springs there instead.
void Tissue::assembleSupported(const std::vector<bool>& onSides) {
  const auto asm_ = assemble(mesh_, elem_mat_, cfg_.lumped_mass);
  const int N = mesh_.nodeCount();
  held_.assign(static_cast<std::size_t>(2 * N), false);
  Eigen::SparseMatrix<double> Kfull = asm_.K;
  if (cfg_.support_stiffness > 0.0) {
    Kfull += boundarySprings(mesh_, cfg_.support_stiffness, cfg_.material.thickness);
  } else {
    for (int i = 0; i < N; ++i)
      if (onSides[static_cast<std::size_t>(i)]) held_[static_cast<std::size_t>(2 * i)] = held_[static_cast<std::size_t>(2 * i + 1)] = true;
  }
  map_ = makeDofMap(2 * N, held_);
  K_ = restrictToFree(Kfull, map_);
  M_ = restrictToFree(asm_.M, map_);
}

// Path: per depth column the node nearest to the reference axis line (axis within
// 45 deg of the depth direction), from the entry face on; held nodes excluded.
void Tissue::pickPath(const Eigen::Vector2d& entry, const std::vector<bool>& onSides) {
  if (!(t_.x() > std::sqrt(0.5) - 1e-12))
    throw SolverError("realtime2d: the needle axis must be within 45 degrees of the entry-face normal");
  for (int i = 0; i < mesh_.nx; ++i) {
    const double s = (mesh_.xs[static_cast<std::size_t>(i)] - entry.x()) / t_.x();
    if (s < -1e-12) continue;
    const double y = entry.y() + s * t_.y();
    const auto it = std::min_element(mesh_.ys.begin(), mesh_.ys.end(),
                                     [&](double a, double b) { return std::abs(a - y) < std::abs(b - y); });
    const int j = static_cast<int>(it - mesh_.ys.begin());
    const int node = mesh_.node(i, j);
    if (held_[static_cast<std::size_t>(2 * node)] || (cfg_.support_stiffness <= 0.0 && onSides[static_cast<std::size_t>(node)]))
      continue;
    const Eigen::Vector2d d = mesh_.nodes.col(node) - entry;
    path_.push_back({node, d.dot(t_), d.dot(n_)});
  }
  if (path_.empty()) throw SolverError("realtime2d: no mesh node lies on the needle path");
  for (const auto& p : path_)
    pdof_.push_back({map_.free_of_dof[static_cast<std::size_t>(2 * p.node)],
                     map_.free_of_dof[static_cast<std::size_t>(2 * p.node + 1)]});
}

void Tissue::makeIntegrator(double dt) {
  const auto& cfg = cfg_;
  PathMap pm{&pdof_, t_, n_};
  materials::Prony prony{cfg.prony};
  prony.validate();
  Backend chosen = cfg.backend;
  if (chosen == Backend::Auto) chosen = map_.freeCount() <= cfg.modal_max_dofs ? Backend::Modal : Backend::Reduced;
  const double a = cfg.rayleigh_alpha, b = cfg.rayleigh_beta;
  if (chosen == Backend::Modal) {
    impl_ = std::make_unique<ModalIntegrator>(K_, M_, a, b, pm, prony);
  } else if (chosen == Backend::Reduced) {
    // Keep the modes whose Rayleigh creep rate beta w^2 is below 20/dt (their inertia
    // matters within a step); all faster ones are residual (quasi-static creep).
    double cutoff = cfg.reduced_cutoff;
    if (!(cutoff > 0.0)) cutoff = b > 0.0 ? std::sqrt(20.0 / (b * dt)) : 2.0 / dt;
    impl_ = std::make_unique<ReducedIntegrator>(K_, M_, a, b, pm, cutoff, cfg.reduced_max_modes, prony);
  } else {
    impl_ = std::make_unique<DirectIntegrator>(K_, M_, a, b, pm, prony);
  }
  // Conditionally stable Newmark: dt w_max <= 1 / sqrt(gamma/2 - beta) (undamped limit).
  dt_limit_ = std::numeric_limits<double>::infinity();
  if (cfg.newmark.beta < 0.5 * cfg.newmark.gamma && !cfg.newmark.unconditionallyStable())
    dt_limit_ = 1.0 / (std::sqrt(0.5 * cfg.newmark.gamma - cfg.newmark.beta) * highestFrequency());
  checkStable(dt);
  nm_ = NewmarkCoefficients(cfg.newmark, dt);
  impl_->prepare(nm_);
}

Tissue::~Tissue() = default;
Tissue::Tissue(Tissue&&) noexcept = default;
Tissue& Tissue::operator=(Tissue&&) noexcept = default;

Backend Tissue::backend() const { return impl_->kind(); }
void Tissue::checkStable(double dt) const {
  if (dt > dt_limit_)
    throw SolverError(fmt::format(
        "realtime2d: time step {:g} s exceeds the stability limit {:g} s of Newmark gamma = {:g}, beta = {:g} "
        "for this mesh (highest frequency {:.4g} rad/s; limit dt w_max <= 1/sqrt(gamma/2 - beta)). Use a "
        "smaller time step, a coarser mesh, or gamma = 0.5, beta = 0.25 (unconditionally stable)",
        dt, dt_limit_, cfg_.newmark.gamma, cfg_.newmark.beta,
        1.0 / (std::sqrt(0.5 * cfg_.newmark.gamma - cfg_.newmark.beta) * dt_limit_)));
}

void Tissue::setTimeStep(double dt) {
  if (dt == nm_.dt) return;
  checkStable(dt);
  nm_ = NewmarkCoefficients(cfg_.newmark, dt);
  impl_->prepare(nm_);
}
const Eigen::MatrixXd& Tissue::pathCompliance() const { return impl_->S(); }
void Tissue::predict() { impl_->predict(u0P_); }
const Eigen::VectorXd& Tissue::predictedPath() const { return u0P_; }

void Tissue::commit(const Eigen::VectorXd& f) {
  impl_->commit(f);
  // Path state: u = u0 + S f exactly; v and a by eqs 3.2-3.3 on those DOFs.
  const auto& c = nm_;
  const double gam = cfg_.newmark.gamma;
  for (int k = 0; k < pathDofs(); ++k) {
    double u = u0P_[k];
    for (int l = 0; l < pathDofs(); ++l)
      if (f[l] != 0.0) u += impl_->S()(k, l) * f[l];
    const double an = c.a0 * (u - pu_[k]) - c.a2 * pv_[k] - c.a3 * pa_[k];
    pv_[k] += c.dt * ((1.0 - gam) * pa_[k] + gam * an);
    pa_[k] = an;
    pu_[k] = u;
  }
  dirty_ = true;
}

void Tissue::refreshFull() const {
  if (!dirty_) return;
  impl_->fullState(fu_, fv_);
  for (int k = 0; k < map_.freeCount(); ++k) {
    full_u_[map_.dof_of_free[static_cast<std::size_t>(k)]] = fu_[k];
    full_v_[map_.dof_of_free[static_cast<std::size_t>(k)]] = fv_[k];
  }
  dirty_ = false;
}
const Eigen::VectorXd& Tissue::displacement() const { refreshFull(); return full_u_; }

Eigen::Vector2d Tissue::nodeDisplacement(int node) const {
  Eigen::Vector2d u = Eigen::Vector2d::Zero();
  for (int c = 0; c < 2; ++c) {
    const int k = map_.free_of_dof[static_cast<std::size_t>(2 * node + c)];
    if (k >= 0) u[c] = dirty_ ? impl_->freeDisplacement(k) : full_u_[2 * node + c];
  }
  return u;
}

Eigen::Vector2d Tissue::regionDisplacement(std::size_t region) const {
  Eigen::Vector2d u = Eigen::Vector2d::Zero();
  const auto& nodes = region_nodes_.at(region);
  for (int n : nodes) u += nodeDisplacement(n);
  return u / static_cast<double>(nodes.size());
}

Eigen::Matrix4Xd Tissue::elementStresses() const {
  const auto& u = displacement();
  Eigen::Matrix4Xd s(4, mesh_.elementCount());
  for (int e = 0; e < mesh_.elementCount(); ++e) {
    Eigen::Matrix<double, 2, 4> xy;
    Eigen::Matrix<double, 8, 1> ue;
    for (int a = 0; a < 4; ++a) {
      const int n = mesh_.quads(a, e);
      xy.col(a) = mesh_.nodes.col(n);
      ue.segment<2>(2 * a) = u.segment<2>(2 * n);
    }
    const auto& m = elem_mat_[static_cast<std::size_t>(e)];
    const Eigen::Vector3d sig = quadCentreStress(xy, elasticity(m), ue);
    s.col(e) << sig, m.plane_strain ? m.nu * (sig[0] + sig[1]) : 0.0;
  }
  return s;
}
const Eigen::VectorXd& Tissue::velocity() const { refreshFull(); return full_v_; }

double Tissue::kineticEnergy() const {
  refreshFull();
  return 0.5 * fv_.dot(M_ * fv_);
}
double Tissue::strainEnergy() const {
  refreshFull();
  return 0.5 * fu_.dot(K_ * fu_);
}

void Tissue::setState(const Eigen::VectorXd& u, const Eigen::VectorXd& v) {
  const int n = map_.freeCount();
  Eigen::VectorXd uf(n), vf(n);
  for (int k = 0; k < n; ++k) {
    uf[k] = u[map_.dof_of_free[static_cast<std::size_t>(k)]];
    vf[k] = v[map_.dof_of_free[static_cast<std::size_t>(k)]];
  }
  const Eigen::SparseMatrix<double> C = cfg_.rayleigh_alpha * M_ + cfg_.rayleigh_beta * K_;
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> mf(M_);
  const Eigen::VectorXd rhs = -(C * vf + K_ * uf);
  const Eigen::VectorXd af = mf.solve(rhs);
  impl_->setState(uf, vf, af);
  PathMap pm{&pdof_, t_, n_};
  for (int k = 0; k < pathDofs(); ++k) {
    pu_[k] = pm.gather(uf, k); pv_[k] = pm.gather(vf, k); pa_[k] = pm.gather(af, k);
  }
  dirty_ = true;
}

double Tissue::highestFrequency() const {
  // Power iteration on M^-1 K (Rayleigh quotient), deterministic start vector.
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> mf(M_);
  Eigen::VectorXd x = Eigen::VectorXd::LinSpaced(M_.rows(), 1.0, 2.0);
  for (Eigen::Index i = 0; i < x.size(); i += 2) x[i] = -x[i];
  double lam = 0.0;
  for (int it = 0; it < 300; ++it) {
    Eigen::VectorXd y = mf.solve(K_ * x);
    const double nl = x.dot(K_ * x) / x.dot(M_ * x);
    x = y / y.norm();
    if (it > 10 && std::abs(nl - lam) < 1e-6 * nl) { lam = nl; break; }
    lam = nl;
  }
  return std::sqrt(std::max(lam, 0.0));
}

Eigen::VectorXd Tissue::staticSolve(const Eigen::VectorXd& f) const {
  const int n = map_.freeCount();
  Eigen::VectorXd ff(n);
  for (int k = 0; k < n; ++k) ff[k] = f[map_.dof_of_free[static_cast<std::size_t>(k)]];
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> kf(K_);
  if (kf.info() != Eigen::Success) throw SolverError("realtime2d: the tissue stiffness is singular (no supports?)");
  const Eigen::VectorXd uf = kf.solve(ff);
  Eigen::VectorXd u = Eigen::VectorXd::Zero(f.size());
  for (int k = 0; k < n; ++k) u[map_.dof_of_free[static_cast<std::size_t>(k)]] = uf[k];
  return u;
}

}  // namespace needlesim::realtime2d
