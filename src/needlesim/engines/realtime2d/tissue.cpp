#include "needlesim/engines/realtime2d/tissue.hpp"

#include <Eigen/SparseCholesky>
#include <fmt/format.h>
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "needlesim/core/error.hpp"
#include "needlesim/engines/realtime2d/tissue_integrators.hpp"

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
