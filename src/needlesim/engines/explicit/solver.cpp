#include "needlesim/engines/explicit/solver.hpp"

#include "needlesim/engines/explicit/cohesive_sleeve.hpp"
#include "needlesim/engines/explicit/cohesive_wedge.hpp"
#include "needlesim/engines/explicit/path_needle.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "needlesim/contact/coulomb.hpp"
#include "needlesim/contact/penalty.hpp"
#include "needlesim/core/error.hpp"
#include "needlesim/materials/fast_stress.hpp"
#include "needlesim/engines/explicit/cohesive_wedge.hpp"

namespace needlesim::explicit_fe {

using Eigen::Matrix3d;
using Eigen::Vector3d;
using Voigt = Eigen::Matrix<double, 6, 1>;

Material Material::fromSpec(const materials::MaterialSpec& spec) {
  Material m;
  m.law = materials::Hyperelastic::fromSpec(spec);
  m.prony.terms = spec.prony;
  m.prony.validate();
  m.density = spec.density;
  if (!(m.density > 0)) throw Error("material '" + spec.name + "': density must be > 0 kg/m^3");
  return m;
}

namespace {

// Natural coordinates of the hex8 and quad4 nodes.
constexpr double kHexXi[8][3] = {{-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1},
                                 {-1, -1, 1},  {1, -1, 1},  {1, 1, 1},  {-1, 1, 1}};
constexpr double kQuadXi[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
// Flanagan-Belytschko (1981) hourglass base vectors.
constexpr double kHexH[4][8] = {{1, 1, -1, -1, -1, -1, 1, 1},
                                {1, -1, -1, 1, -1, 1, 1, -1},
                                {1, -1, 1, -1, 1, -1, 1, -1},
                                {-1, 1, -1, 1, 1, -1, 1, -1}};
constexpr double kQuadH[4] = {1, -1, 1, -1};

inline Voigt toVoigt(const Matrix3d& S) {
  Voigt v;
  v << S(0, 0), S(1, 1), S(2, 2), S(0, 1), S(1, 2), S(0, 2);
  return v;
}
inline Matrix3d fromVoigt(const Voigt& v) {
  Matrix3d S;
  S << v[0], v[3], v[5], v[3], v[1], v[4], v[5], v[4], v[2];
  return S;
}

// Flanagan-Belytschko hourglass forces of one element added to fe (gamma: nhg x NPE shape vectors, K the
// DIM x DIM stiffness); returns the hourglass energy, sets hs to the largest zig-zag amplitude / size.
template <int NPE, int DIM>
[[gnu::always_inline]] inline double hourglassForces(const double* K, const double* gamma, int nhg, const double (&ue)[NPE][DIM],
                              double sumG, double* fe, double& hs) {
  double ehg = 0.0;
  for (int m = 0; m < nhg; ++m) {
    const double* gam = gamma + static_cast<std::size_t>(m) * NPE;
    double q[DIM] = {}, Kq[DIM] = {};
    for (int a = 0; a < NPE; ++a)
      for (int i = 0; i < DIM; ++i) q[i] += gam[a] * ue[a][i];
    for (int i = 0; i < DIM; ++i)
      for (int j = 0; j < DIM; ++j) Kq[i] += K[i * DIM + j] * q[j];
    for (int a = 0; a < NPE; ++a)
      for (int i = 0; i < DIM; ++i) fe[a * DIM + i] += gam[a] * Kq[i];
    double qq = 0.0;
    for (int i = 0; i < DIM; ++i) ehg += 0.5 * q[i] * Kq[i], qq += q[i] * q[i];
    hs = std::max(hs, std::sqrt(qq * sumG) / NPE);  // zig-zag amplitude / element size
  }
  return ehg;
}

// Below this many elements / nodes a loop runs serially: thread start-up and
// barriers cost more than the work (and spin badly on a loaded machine).
constexpr int kParallelMin = 4000;

std::string fmtNum(double v) {
  std::ostringstream o;
  o.precision(4);
  o << v;
  return o.str();
}

// x less the node's displacement u (dim components) along the unit direction e.
Vector3d lessDisplacementAlong(const Vector3d& x, const double* u, int dim, const Vector3d& e) {
  double ue = 0.0;
  for (int i = 0; i < dim; ++i) ue += u[i] * e[i];
  return x - ue * e;
}

}  // namespace

ExplicitSolver::ExplicitSolver(Mesh mesh, std::vector<Material> materials, SolverOptions options)
    : mesh_(std::move(mesh)), mats_(std::move(materials)), opt_(options) {
  dim_ = mesh_.dim;
  npe_ = nodesPerElement(mesh_.type);
  nel_ = mesh_.elements();
  nnode_ = mesh_.nodes();
  nhg_ = mesh_.type == ElementType::Quad4 ? 1 : mesh_.type == ElementType::Hex8 ? 4 : 0;
  validateInput();
  allocateElementData();

  for (auto& m : mats_) {
    const auto [lam, mu] = m.law.initialLame();
    matWaveModulus_.push_back(lam + 2 * mu);
    double K = lam + 2.0 / 3.0 * mu;
    matBulk_.push_back(K);
    // bending modulus of the hourglass stiffness: plane-strain E' (2D) or E (3D); -> 4 mu, 3 mu as nu -> 1/2
    matShear_.push_back(dim_ == 2 ? 4 * mu * (lam + mu) / (lam + 2 * mu) : materials::youngPoisson(K, mu).E);
  }

  minSize_ = std::numeric_limits<double>::infinity();
  for (int e = 0; e < nel_; ++e) {
    referenceGeometry(e);
    hourglassVectors(e);
    elementStiffnessAndMass(e);
  }
  allocatePronyStates();
  buildNodeSlots();
  lumpedMassAndNodeData();
  releaseDistance_ = minSize_;
  // stable step of the initial mesh, so that timeStep() is meaningful before the first step
  elementForces(0.0);
  elementUpdates_ = 0;
  computeStableStep();
}

void ExplicitSolver::validateInput() {
  if (elementDim(mesh_.type) != dim_) throw Error("mesh dimension does not match its element type");
  if (mats_.empty()) throw Error("explicit FE: no material");
  if (mesh_.region.size() != static_cast<std::size_t>(nel_)) mesh_.region.assign(nel_, 0);
  if (!(opt_.massScaling >= 1.0)) throw Error("explicit FE: mass scaling factor must be >= 1");
  if (!(opt_.cfl > 0 && opt_.cfl <= 1.0)) throw Error("explicit FE: CFL factor must lie in (0, 1]");
  if (!(opt_.contactPenalty > 0 && opt_.contactPenalty <= 1e4))
    throw Error("explicit FE: contact penalty must lie in (0, 1e4] (multiple of m/dt^2)");
  if (!(opt_.stickPenalty > 0 && opt_.stickPenalty < 1.0))
    throw Error("explicit FE: friction stick penalty must lie in (0, 1) (fraction of m/dt^2)");
}

void ExplicitSolver::allocateElementData() {
  grad0_.assign(static_cast<std::size_t>(nel_) * npe_ * dim_, 0.0);
  gamma_.assign(static_cast<std::size_t>(nel_) * std::max(nhg_, 1) * npe_, 0.0);
  vol0_.assign(nel_, 0.0);
  rho_.assign(nel_, 0.0);
  hgStiff_.assign(static_cast<std::size_t>(nel_) * dim_ * dim_, 0.0);
  mat_.assign(nel_, 0);
  fe_.assign(static_cast<std::size_t>(nel_) * npe_ * dim_, 0.0);
  dtElem_.assign(nel_, 0.0);
  wElem_.assign(nel_, 0.0);
  hgElem_.assign(nel_, 0.0);
  hgStrain_.assign(nel_, 0.0);
  failElem_.assign(nel_, 0);
  spk2_.assign(static_cast<std::size_t>(nel_) * 6, 0.0);
}

// Natural derivatives at the centroid, Jacobian, gradients dN/dX and reference volume of element e
// (an element given in inverted node order is mirrored once).
void ExplicitSolver::referenceGeometry(int e) {
  const int reg = mesh_.region[e];
  if (reg < 0 || reg >= static_cast<int>(mats_.size()))
    throw Error("element " + std::to_string(e) + " has region " + std::to_string(reg) + " but only " +
                std::to_string(mats_.size()) + " materials are given");
  mat_[e] = reg;
  int* cn = &mesh_.conn[static_cast<std::size_t>(e) * npe_];
  auto X = [&](int a, int i) { return mesh_.X[static_cast<std::size_t>(cn[a]) * dim_ + i]; };
  Eigen::MatrixXd dN(npe_, dim_);
  double volFactor = 1.0;
  for (int pass = 0; pass < 2; ++pass) {
    switch (mesh_.type) {
      case ElementType::Quad4:
        for (int a = 0; a < 4; ++a)
          for (int i = 0; i < 2; ++i) dN(a, i) = 0.25 * kQuadXi[a][i];
        volFactor = 4.0;
        break;
      case ElementType::Hex8:
        for (int a = 0; a < 8; ++a)
          for (int i = 0; i < 3; ++i) dN(a, i) = 0.125 * kHexXi[a][i];
        volFactor = 8.0;
        break;
      case ElementType::Tri3:
        dN << -1, -1, 1, 0, 0, 1;
        volFactor = 0.5;
        break;
      case ElementType::Tet4:
        dN << -1, -1, -1, 1, 0, 0, 0, 1, 0, 0, 0, 1;
        volFactor = 1.0 / 6.0;
        break;
    }
    Eigen::MatrixXd Jm = Eigen::MatrixXd::Zero(dim_, dim_);
    for (int a = 0; a < npe_; ++a)
      for (int i = 0; i < dim_; ++i)
        for (int j = 0; j < dim_; ++j) Jm(i, j) += X(a, i) * dN(a, j);
    double det = Jm.determinant();
    if (det > 0) {
      Eigen::MatrixXd G = dN * Jm.inverse();  // npe x dim: dN_a/dX_j
      for (int a = 0; a < npe_; ++a)
        for (int j = 0; j < dim_; ++j) grad0_[(static_cast<std::size_t>(e) * npe_ + a) * dim_ + j] = G(a, j);
      vol0_[e] = volFactor * det;
      break;
    }
    if (pass == 1 || det == 0.0 || !std::isfinite(det))
      throw Error("explicit FE: element " + std::to_string(e) + " has zero or undefined volume");
    // Inverted node order (e.g. a clockwise Gmsh quad): mirror it once.
    switch (mesh_.type) {
      case ElementType::Quad4: std::swap(cn[1], cn[3]); break;
      case ElementType::Tri3: std::swap(cn[1], cn[2]); break;
      case ElementType::Tet4: std::swap(cn[1], cn[2]); break;
      case ElementType::Hex8:
        std::swap(cn[1], cn[3]);
        std::swap(cn[5], cn[7]);
        break;
    }
  }
}

void ExplicitSolver::hourglassVectors(int e) {
  const int* cn = &mesh_.conn[static_cast<std::size_t>(e) * npe_];
  auto X = [&](int a, int i) { return mesh_.X[static_cast<std::size_t>(cn[a]) * dim_ + i]; };
  const double* g = &grad0_[static_cast<std::size_t>(e) * npe_ * dim_];
  // Hourglass shape vectors gamma = h - (h . X) grad N  (orthogonal to linear fields).
  for (int m = 0; m < nhg_; ++m) {
    double hx[3] = {0, 0, 0};
    for (int a = 0; a < npe_; ++a) {
      double h = dim_ == 2 ? kQuadH[a] : kHexH[m][a];
      for (int i = 0; i < dim_; ++i) hx[i] += h * X(a, i);
    }
    for (int a = 0; a < npe_; ++a) {
      double h = dim_ == 2 ? kQuadH[a] : kHexH[m][a];
      double gam = h;
      for (int i = 0; i < dim_; ++i) gam -= hx[i] * g[a * dim_ + i];
      gamma_[(static_cast<std::size_t>(e) * nhg_ + m) * npe_ + a] = gam;
    }
  }
}

// Hourglass stiffness, smallest element size, density with mass scaling of element e.
void ExplicitSolver::elementStiffnessAndMass(int e) {
  const double* g = &grad0_[static_cast<std::size_t>(e) * npe_ * dim_];
  // Hourglass stiffness tensor K = eps E_b V0 G / (3 |h|^2), G_ij = sum_a dN_a/dX_i dN_a/dX_j: exact
  // pure bending of a rectangular element for eps = 1 (Belytschko & Bindeman 1993 physical
  // stabilization, in tensor form); E_b never contains the bulk modulus, so no volumetric locking.
  double sumG = 0.0;
  for (int i = 0; i < dim_; ++i)
    for (int j = 0; j < dim_; ++j) {
      double Gij = 0;
      for (int a = 0; a < npe_; ++a) Gij += g[a * dim_ + i] * g[a * dim_ + j];
      if (i == j) sumG += Gij;
      if (nhg_ > 0)
        hgStiff_[static_cast<std::size_t>(e) * dim_ * dim_ + i * dim_ + j] =
            opt_.hourglass * matShear_[mat_[e]] * vol0_[e] * Gij / (3.0 * npe_);
    }
  minSize_ = std::min(minSize_, 1.0 / std::sqrt(0.5 * sumG * npe_ / dim_));
  // Density and mass scaling (factor, then to the target step).
  double rho = mats_[mat_[e]].density * opt_.massScaling;
  double c = std::sqrt(matWaveModulus_[mat_[e]] / rho);
  double dte = opt_.cfl * 2.0 / (c * std::sqrt(npe_ * sumG));
  if (opt_.targetTimeStep > 0 && dte < opt_.targetTimeStep) rho *= std::pow(opt_.targetTimeStep / dte, 2);
  rho_[e] = rho;
  physicalMass_ += mats_[mat_[e]].density * vol0_[e];
}

// Prony states (allocated once).
void ExplicitSolver::allocatePronyStates() {
  prony_.resize(nel_);
  for (int e = 0; e < nel_; ++e) {
    const auto& pr = mats_[mat_[e]].prony;
    if (pr.terms.empty()) continue;
    prony_[e].H.assign(pr.terms.size(), Voigt::Zero());
    prony_[e].SePrev = Voigt::Zero();
    prony_[e].started = true;
  }
}

// Node -> element slots (CSR) for a race-free gather.
void ExplicitSolver::buildNodeSlots() {
  nodeStart_.assign(nnode_ + 1, 0);
  for (int s = 0; s < nel_ * npe_; ++s) nodeStart_[mesh_.conn[s] + 1]++;
  for (int n = 0; n < nnode_; ++n) nodeStart_[n + 1] += nodeStart_[n];
  nodeSlots_.assign(nel_ * npe_, 0);
  {
    std::vector<int> fill(nodeStart_.begin(), nodeStart_.end() - 1);
    for (int s = 0; s < nel_ * npe_; ++s) nodeSlots_[fill[mesh_.conn[s]]++] = s;
  }
}

// Lumped mass rho V0 / n_a per node; node and contact arrays.
void ExplicitSolver::lumpedMassAndNodeData() {
  const std::size_t ndof = static_cast<std::size_t>(nnode_) * dim_;
  mass_.assign(nnode_, 0.0);
  for (int e = 0; e < nel_; ++e)
    for (int a = 0; a < npe_; ++a) mass_[mesh_.conn[static_cast<std::size_t>(e) * npe_ + a]] += rho_[e] * vol0_[e] / npe_;
  for (int n = 0; n < nnode_; ++n)
    if (!(mass_[n] > 0)) throw Error("explicit FE: node " + std::to_string(n) + " belongs to no element");
  u_.assign(ndof, 0.0);
  vHalf_.assign(ndof, 0.0);
  fint_.assign(ndof, 0.0);
  fext_.assign(ndof, 0.0);
  fcon_.assign(ndof, 0.0);
  react_.assign(ndof, 0.0);
  dofGroup_.assign(ndof, -1);
  contactBody_.assign(nnode_, -1);
  contactK_.assign(nnode_, 0.0);
  contactMu_.assign(nnode_, 0.0);
  contactWedge_.assign(nnode_, 0.0);
  contactFnApplied_.assign(nnode_, 0.0);
  contactTip_.assign(nnode_, 0);
  contactDepth_.assign(nnode_, 0.0);
  contactNrm_.assign(static_cast<std::size_t>(nnode_) * 3, 0.0);
  contactVb_.assign(static_cast<std::size_t>(nnode_) * 3, 0.0);
  penetrationTol_ = opt_.penetrationTolerance > 0 ? opt_.penetrationTolerance : 0.5 * minSize_;
  if (opt_.nodalPressure && nhg_ == 0) {
    anpP_.assign(nel_, 0.0);
    anpB_.assign(static_cast<std::size_t>(nel_) * npe_ * dim_, 0.0);
    anpNode_.assign(nnode_, 0.0);
    anpDp_.assign(nel_, 0.0);
  }
}

int ExplicitSolver::addGroup() {
  groupVelocity_.push_back(0.0);
  groupReaction_.push_back(0.0);
  return static_cast<int>(groupVelocity_.size()) - 1;
}
void ExplicitSolver::addDof(int group, int node, int comp) { dofGroup_[static_cast<std::size_t>(node) * dim_ + comp] = group; }
void ExplicitSolver::addTie(int a, int b) {
  tieA_.push_back(a);
  tieB_.push_back(b);
  tieOn_.push_back(1);
  ftie_.assign(u_.size(), 0.0);
}
void ExplicitSolver::setContactSide(int node, int side) {
  if (contactSide_.empty()) contactSide_.assign(nnode_, 0);
  contactSide_[node] = static_cast<signed char>(side > 0 ? 1 : side < 0 ? -1 : 0);
}
void ExplicitSolver::setCohesive(CohesiveInterface c) {
  if (c.dim() != dim_) throw Error("explicit FE: the cohesive interface's dimension differs from the mesh's");
  coh_.assign(1, std::move(c));
  fcoh_.assign(u_.size(), 0.0);
  cohPairOf_.assign(nnode_, -1);
  for (int p = 0; p < coh_.front().pairs(); ++p) cohPairOf_[coh_.front().node(p, 0)] = cohPairOf_[coh_.front().node(p, 1)] = p;
  cohOmega2_ = coh_.front().maxOmega2(mass_);
  cohesiveForces();
  computeStableStep();
}
void ExplicitSolver::cohesiveForces() {
  if (coh_.empty()) return;
  std::fill(fcoh_.begin(), fcoh_.end(), 0.0);
  coh_.front().addForces(mesh_.X, u_, fcoh_);
  en_.cohesiveStored = coh_.front().stored();
  en_.cohesiveDissipated = coh_.front().dissipated();
}
int ExplicitSolver::activeTies() const {
  int n = 0;
  for (char c : tieOn_) n += c;
  return n;
}

int ExplicitSolver::addPlane(const RigidPlane& p) {
  planes_.push_back(p);
  planes_.back().normal.normalize();
  planeFt_.emplace_back(static_cast<std::size_t>(nnode_) * 3, 0.0);
  planeStage_.emplace_back(Vector3d::Zero());
  return static_cast<int>(planes_.size()) - 1;
}
void ExplicitSolver::setNeedle(const RigidNeedle& n) {
  needle_ = n;
  hasNeedle_ = true;
  needleFt_.assign(static_cast<std::size_t>(nnode_) * 3, 0.0);
  fconNeedle_.assign(u_.size(), 0.0);
  fconFriction_.assign(u_.size(), 0.0);
  if (n.path) contactAxis_.assign(static_cast<std::size_t>(nnode_) * 3, 0.0);
  else contactAxis_.clear();
  needleK_.assign(nnode_, 0.0);
  pose0_ = n.pose;
}
double ExplicitSolver::totalMass() const {
  double s = 0;
  for (double m : mass_) s += m;
  return s;
}

std::string ExplicitSolver::elementWhere(int e) const {
  double c[3] = {0, 0, 0};
  for (int a = 0; a < npe_; ++a)
    for (int i = 0; i < dim_; ++i) c[i] += mesh_.X[static_cast<std::size_t>(mesh_.conn[static_cast<std::size_t>(e) * npe_ + a]) * dim_ + i] / npe_;
  std::string s = "element " + std::to_string(e) + " at (" + fmtNum(c[0] * 1e3) + ", " + fmtNum(c[1] * 1e3);
  if (dim_ == 3) s += ", " + fmtNum(c[2] * 1e3);
  return s + ") mm";
}

void ExplicitSolver::fail(const std::string& cause, const std::string& where, const std::string& remedy) const {
  throw SolverError("explicit FE stopped at t = " + fmtNum(time_) + " s (step " + std::to_string(steps_) +
                    "): " + cause + (where.empty() ? "" : " in " + where) + ". " + remedy);
}

template <int NPE, int DIM>
void ExplicitSolver::internalForces(double dtStep) {
  const double b1 = opt_.bulkViscosityLinear, b2 = opt_.bulkViscosityQuadratic;
  double dtMin = std::numeric_limits<double>::infinity(), eW = 0.0, eHg = 0.0;
  int bad = 0;
  const int nhg = nhg_;
#pragma omp parallel for schedule(static) if (nel_ >= kParallelMin) reduction(min : dtMin) reduction(+ : eW, eHg, bad)
  for (int e = 0; e < nel_; ++e) {
    const int* cn = &mesh_.conn[static_cast<std::size_t>(e) * NPE];
    const double* g = &grad0_[static_cast<std::size_t>(e) * NPE * DIM];
    const Material& mat = mats_[mat_[e]];
    double ue[NPE][DIM], ve[NPE][DIM];
    for (int a = 0; a < NPE; ++a)
      for (int i = 0; i < DIM; ++i) {
        ue[a][i] = u_[static_cast<std::size_t>(cn[a]) * DIM + i];
        ve[a][i] = vHalf_[static_cast<std::size_t>(cn[a]) * DIM + i];
      }
    Matrix3d F = Matrix3d::Identity(), Fd = Matrix3d::Zero();
    for (int a = 0; a < NPE; ++a)
      for (int i = 0; i < DIM; ++i)
        for (int j = 0; j < DIM; ++j) {
          F(i, j) += ue[a][i] * g[a * DIM + j];
          Fd(i, j) += ve[a][i] * g[a * DIM + j];
        }
    const double J = F.determinant();
    double* fe = &fe_[static_cast<std::size_t>(e) * NPE * DIM];
    if (!(J > 0.0) || !std::isfinite(J)) {  // inverted: report after the loop, never throw inside
      failElem_[e] = 1;
      ++bad;
      for (int k = 0; k < NPE * DIM; ++k) fe[k] = 0.0;
      continue;
    }
    Matrix3d S;
    double W;
    materials::fastPk2(mat.law, F, J, S, W);  // neo-Hooke and linear inline (materials/fast_stress.hpp)
    if (!mat.prony.terms.empty()) {
      S = fromVoigt(materials::pronyUpdate(mat.prony, prony_[e], toVoigt(S), dtStep));
    }
    for (int k = 0; k < 6; ++k) spk2_[static_cast<std::size_t>(e) * 6 + k] = toVoigt(S)[k];
    Matrix3d P = F * S;
    // Current gradients -> characteristic length and stable step.
    const Matrix3d Finv = F.inverse();
    if constexpr (NPE == DIM + 1) {
      if (!anpP_.empty()) {  // element pressure and V0 J F^-T grad0 N for the nodal-pressure pass
        anpP_[e] = (F * S * F.transpose()).trace() / (3.0 * J);
        for (int a = 0; a < NPE; ++a)
          for (int i = 0; i < DIM; ++i) {
            double b = 0.0;
            for (int j = 0; j < DIM; ++j) b += Finv(j, i) * g[a * DIM + j];
            anpB_[(static_cast<std::size_t>(e) * NPE + a) * DIM + i] = vol0_[e] * J * b;
          }
      }
    }
    double sumG = 0.0;
    for (int a = 0; a < NPE; ++a) {
      for (int i = 0; i < DIM; ++i) {
        double gi = 0.0;
        for (int j = 0; j < DIM; ++j) gi += Finv(j, i) * g[a * DIM + j];
        sumG += gi * gi;
      }
    }
    const double rho = rho_[e];
    const double c = std::sqrt(matWaveModulus_[mat_[e]] / rho);
    const double Le = 1.0 / std::sqrt(sumG);
    // Bulk viscosity (ABAQUS/Explicit): sigma_bv = rho Le ev (b1 c + b2^2 Le |min(ev, 0)|), ev = tr(D).
    const double ev = (Fd * Finv).trace();
    const double evc = std::min(ev, 0.0);
    const double sbv = rho * Le * ev * (b1 * c - b2 * b2 * Le * evc);
    P += sbv * J * Finv.transpose();
    const double xi = b1 - b2 * b2 * Le * evc / c;
    const double dte = 2.0 / (c * std::sqrt(NPE * sumG)) * (std::sqrt(1.0 + xi * xi) - xi);
    dtElem_[e] = dte;
    dtMin = std::min(dtMin, dte);
    const double V0 = vol0_[e];
    for (int a = 0; a < NPE; ++a)
      for (int i = 0; i < DIM; ++i) {
        double s = 0.0;
        for (int j = 0; j < DIM; ++j) s += P(i, j) * g[a * DIM + j];
        fe[a * DIM + i] = V0 * s;
      }
    double ehg = 0.0, hs = 0.0;
    if constexpr ((NPE == 4 && DIM == 2) || NPE == 8)
      ehg = hourglassForces<NPE, DIM>(&hgStiff_[static_cast<std::size_t>(e) * DIM * DIM],
                                      &gamma_[static_cast<std::size_t>(e) * nhg * NPE], nhg, ue, sumG, fe, hs);
    hgElem_[e] = ehg;
    hgStrain_[e] = hs;
    wElem_[e] = V0 * W;
    eW += V0 * W;
    eHg += ehg;
  }
  elementUpdates_ += nel_;
  if (bad == 0 && !anpP_.empty()) eW += nodalPressureCorrection();
  if (bad > 0) failInverted(bad);
  en_.strain = eW;
  en_.hourglass = eHg;
  dtStable_ = dtMin;
}

void ExplicitSolver::failInverted(int bad) const {
  int e = static_cast<int>(std::find(failElem_.begin(), failElem_.end(), 1) - failElem_.begin());
  Matrix3d F = deformationGradient(e);
  fail("inverted element (det F = " + fmtNum(F.determinant()) + ", " + std::to_string(bad) + " element(s))",
       elementWhere(e),
       "Remedy: refine the mesh where the needle cuts, lower the needle speed or the mass scaling, "
       "raise the bulk viscosity, or (near the tip) use a sharper tip / frictionless tip contact");
}

void ExplicitSolver::gatherForces() {
  const int d = dim_;
#pragma omp parallel for schedule(static) if (nnode_ >= kParallelMin)
  for (int n = 0; n < nnode_; ++n) {
    double f[3] = {0, 0, 0};
    for (int k = nodeStart_[n]; k < nodeStart_[n + 1]; ++k) {
      const double* fe = &fe_[static_cast<std::size_t>(nodeSlots_[k]) * d];
      for (int i = 0; i < d; ++i) f[i] += fe[i];
    }
    for (int i = 0; i < d; ++i) fint_[static_cast<std::size_t>(n) * d + i] = f[i];
  }
}

// Needle contact stiffness of node n: the value k0 = penalty m / (cfl dt_stable)^2 of the step the
// node's contact episode began, kept until the node leaves the needle (docs/models/explicit.md,
// "Contact stiffness"). With k following the stable step the stored 1/2 k g^2 changed without work
// (k rose as the elements at the tip distorted: 18.8 % of the needle work in a 2D cut). An explicit lip
// penalty is capped at kMax in case the step grows back (stability of the explicit lip penalty).
double ExplicitSolver::episodeStiffness(int n, double k0, double kMax) {
  if (opt_.fixedContactStiffness) return k0;  // already one k for the whole run
  double& k = needleK_[n];
  if (!(k > 0)) k = k0;
  k = std::min(k, kMax);
  return k;
}

// The needle's hit on tissue node n at x (the straight needle in `pose`): queryNeedle with the node's lip
// side, or on a cohesive seam lip the wedge of cohesive_wedge.hpp / cohesive_sleeve.hpp; wedgeAxial: the
// axial face force per unit lateral force the needle takes for a wedged lip (0 otherwise).
needle::NeedleHit ExplicitSolver::needleHit(int n, const Vector3d& x, const needle::NeedlePose& pose,
                                            double& wedgeAxial) const {
  const RigidNeedle& nd = needle_;
  const int d = dim_;
  const bool planar = d == 2;
  needle::NeedleHit hit =
      needle::queryNeedle(nd.shape, pose, x, planar, contactSide_.empty() ? 0 : contactSide_[n]);
  // Wedge on a still-cohesive seam pair (docs/models/cohesive.md "The point wedges the seam
  // open"): the lip nodes of a pair that is not fully damaged are pushed across the cut line
  // only, each to its own side, by the lateral gap to the needle's face (the axial push of the
  // inclined faces would shove the closed pair ahead of the point); the needle takes the axial
  // reaction that makes its work match: one gap function per lip (cohesive_wedge.hpp: 2D bevel,
  // 3D bevel with the seam through the axis or the slit through the sharp point, 3D cone) at the node's
  // reference axial station.
  // (bevel, 2D and 3D: also once fully damaged: a lip dragged across the axis plane by its partner (3D), or
  // a wall-side lip released above the point's line by the chisel (2D), would otherwise meet the lip side
  // rule of queryNeedle with a jump in depth: 2D cut with G_c = 2 J/m^2, h = 0.125 mm: needle balance 8.4 %
  // with the switch to queryNeedle at d = 1, 0.26 % without)
  // (the node-release slit of a 3D block, setWedgeLips: every lip node, tied or released)
  const bool lip = (!cohPairOf_.empty() && cohPairOf_[n] >= 0 &&
                    (coh_.front().state(cohPairOf_[n]).damage < 1.0 || nd.shape.tip == TipType::Bevel)) ||
                   (wedgeLips_ && !planar && !contactSide_.empty() && contactSide_[n] != 0);
  if (lip && !contactSide_.empty() && contactSide_[n] != 0 &&
      (nd.shape.tip == TipType::Bevel || nd.shape.tip == TipType::Conical)) {
    // the gap at the node's reference axial station; for a 3D bevel's seam or slit also at its
    // reference coordinate along the seam, which sets the half chord sqrt(R^2 - b^2): the gap then varies
    // with the current position only across the seam, where the lip is pushed, so the push k gap is the
    // gradient of the penalty potential 1/2 k gap^2 (Wriggers, Computational Contact Mechanics, 2006) and
    // the needle's reaction its time derivative (docs/models/cohesive.md "3D: the seam plane and the cone wedge")
    const double* un = &u_[static_cast<std::size_t>(n) * d];
    Vector3d xw = lessDisplacementAlong(x, un, d, pose.axis);
    if (!planar && nd.shape.tip == TipType::Bevel && sleeveRadius_ <= 0)
      xw = lessDisplacementAlong(xw, un, d, pose.axis.cross(pose.bevelSide));
    needle::NeedleHit wh;
    const Vector3d xRef(mesh_.X[static_cast<std::size_t>(n) * d], mesh_.X[static_cast<std::size_t>(n) * d + 1],
                        d == 3 ? mesh_.X[static_cast<std::size_t>(n) * d + 2] : 0.0);
    bool in = sleeveRadius_ > 0
                        ? sleeveWedge(nd.shape, pose, xw, contactSide_[n], sleeveRadius_, wh, wedgeAxial, &xRef)
                        : lipWedge(nd.shape, pose, xw, contactSide_[n], lipSeam(), wh, wedgeAxial);
    if (in && wedgeLips_ && cohPairOf_.empty()) in = lessStartOverlap(n, xRef, wh);
    hit = in ? wh : needle::NeedleHit{};
  } else if (lip && hit.inside && hit.face == needle::NeedleFace::Tip && nd.shape.tip == TipType::Bevel) {
    const double c = hit.normal.dot(pose.bevelSide);
    if (std::abs(c) > 1e-3) {
      wedgeAxial = hit.normal.dot(pose.axis) / std::abs(c);
      hit.depth /= std::abs(c);
      hit.normal = (c > 0 ? 1.0 : -1.0) * pose.bevelSide;
    }
  }
  return hit;
}

// A node-release lip that the wedge already overlapped at the start (a needle that starts with its tip in the
// tissue: the bevel face over the lips behind the point) is opened over the first reach of travel, the chisel's
// reach R / tan(kLipRampAngle), instead of at once:
// its gap less its gap at the start times the share of that reach still to travel (the opening rate at most
// doubles; LS-DYNA's tracked initial penetrations do the same for contact surfaces that start overlapped).
// False when no gap is left.
bool ExplicitSolver::lessStartOverlap(int n, const Vector3d& xRef, needle::NeedleHit& hit) const {
  const RigidNeedle& nd = needle_;
  const double reach = nd.shape.radius / std::tan(needle::kLipRampAngle);
  const double left = 1.0 - (nd.pose.tip - pose0_.tip).dot(pose0_.axis) / reach;
  if (!(left > 0.0)) return true;
  needle::NeedleHit h0;
  double slope0 = 0.0;
  if (!lipWedge(nd.shape, pose0_, xRef, contactSide_[n], lipSeam(), h0, slope0)) return true;
  hit.depth -= h0.depth * left;
  return hit.depth > 0.0;
}

// Needle contact stiffness of node n for this step: k = contact_penalty m / dtPen^2 (contact/penalty.hpp).
double ExplicitSolver::needleContactStiffness(int n, double dtPen) {
  // cohesive seam lips keep an explicit-range penalty, the one the wedge model was built with: the
  // contact_penalty itself when it is <= 1, else lipPenalty (docs/models/explicit.md)
  const bool seamLip = sleeveRadius_ <= 0 && !cohPairOf_.empty() && cohPairOf_[n] >= 0;  // sleeve: full penalty
  const double lipPen = opt_.contactPenalty <= 1.0 ? opt_.contactPenalty : opt_.lipPenalty;
  // (an explicit lip penalty stays below 4 - (2 cfl)^2 = 0.76 m/dt^2 at cfl 0.9: kLipPenaltyMax)
  double k = seamLip ? episodeStiffness(n, contact::massPenalty(lipPen, mass_[n], dtPen),
                                        contact::massPenalty(std::max(kLipPenaltyMax, lipPen), mass_[n], dtPen))
                     : episodeStiffness(n, contact::massPenalty(opt_.contactPenalty, mass_[n], dtPen),
                                        std::numeric_limits<double>::infinity());
  // sleeve lips (implicit contact, any k is stable): at least 10x the pair's cohesive spring K A, so the wall
  // holds t_c with a gap of delta_0 / 10 instead of storing (and releasing at failure) a large penalty energy
  if (sleeveRadius_ > 0 && !cohPairOf_.empty() && cohPairOf_[n] >= 0)
    k = std::max(k, 10.0 * coh_.front().law(cohPairOf_[n]).stiffness * coh_.front().tributaryLength(cohPairOf_[n]));
  return k;
}

void ExplicitSolver::failNeedlePenetration(double maxPen) const {
  const RigidNeedle& nd = needle_;
  fail("needle contact penetration " + fmtNum(maxPen * 1e3) + " mm exceeds the tolerance " +
           fmtNum(penetrationTol_ * 1e3) + " mm",
       "the needle contact zone (tip at " + fmtNum(nd.pose.tip.x() * 1e3) + ", " + fmtNum(nd.pose.tip.y() * 1e3) +
           ", " + fmtNum(nd.pose.tip.z() * 1e3) + " mm)",
       "Remedy: raise model.explicit.contact_penalty, lower the insertion speed or the mass "
       "scaling, or refine the mesh so that tissue nodes resolve the needle tip");
}

// Penalty from the stable step, not the (possibly shortened) last step: k = penalty m / dt_stable^2.
// The normal force is completed at the end of the next step (contact_normal.cpp); the friction
// stick spring stays explicit with the stable fraction stickPenalty. fixedContactStiffness keeps
// the step of the first evaluation (a conservative penalty, docs/models/cohesive.md).
double ExplicitSolver::contactTimeStep() {
  if (dtPenFixed_ == 0.0) dtPenFixed_ = opt_.cfl * dtStable_;
  return opt_.fixedContactStiffness ? dtPenFixed_ : opt_.cfl * dtStable_;
}

void ExplicitSolver::contactForces(double dtStep) {
  std::fill(fcon_.begin(), fcon_.end(), 0.0);
  std::fill(contactBody_.begin(), contactBody_.end(), -1);
  extContactForceLast_ = extContactForce_;
  extContactForce_.setZero();
  if (dtStep <= 0) return;
  const double dtPen = contactTimeStep();
  const double stick = std::min(opt_.contactPenalty, opt_.stickPenalty);  // stick spring: k = stick m / dtPen^2
  const ContactStep cs{dtStep, dtPen, stick};
  planeContactForces(cs);
  if (hasNeedle_) needleContactForces(cs);
}

void ExplicitSolver::planeContactForces(const ContactStep& cs) {
  const int d = dim_;
  const double dtStep = cs.dtStep, dtPen = cs.dtPen, stick = cs.stick;
  for (std::size_t p = 0; p < planes_.size(); ++p) {
    RigidPlane& pl = planes_[p];
    std::vector<double>& ftH = planeFt_[p];
    double fx = 0, fy = 0, fz = 0;
#pragma omp parallel for schedule(static) if (nnode_ >= kParallelMin) reduction(+ : fx, fy, fz)
    for (int n = 0; n < nnode_; ++n) {
      Vector3d x, v;
      nodeState(n, x, v);
      double gap = (x - pl.point).dot(pl.normal);
      double* ft = &ftH[static_cast<std::size_t>(n) * 3];
      if (gap >= 0) {
        ft[0] = ft[1] = ft[2] = 0;
        continue;
      }
      const double k = contact::massPenalty(opt_.contactPenalty, mass_[n], dtPen);
      const double fn = contact::penaltyForce(k, -gap);
      Vector3d f = fn * pl.normal;
      recordNormalContact(n, 2 + static_cast<int>(p), pl.normal, k, -gap, pl.velocity, pl.friction);
      if (pl.friction > 0) {
        // elastic stick predictor, return map onto the Coulomb cone (contact/coulomb.hpp)
        const Vector3d t = contact::stickSpringFriction(Vector3d(ft[0], ft[1], ft[2]), pl.normal, v - pl.velocity,
                                                        contact::massPenalty(stick, mass_[n], dtPen) * dtStep,
                                                        pl.friction * fn);
        ft[0] = t[0], ft[1] = t[1], ft[2] = t[2];
        f += t;
      }
      for (int i = 0; i < d; ++i) fcon_[static_cast<std::size_t>(n) * d + i] += f[i];
      fx -= f[0], fy -= f[1], fz -= f[2];
    }
    planeStage_[p] = Vector3d(fx, fy, fz);  // pl.force: completed by normalContactCorrection
  }
}

// Node n inside the needle (hit): its penalty normal force and stick-spring friction on the tissue
// (fcon_, fconNeedle_, fconFriction_, the stick state needleFt_), recorded for the normal correction.
ExplicitSolver::NeedleNodeForce ExplicitSolver::needleNodeForce(int n, const Vector3d& v, const Vector3d& vb,
                                                                const needle::NeedlePose& pose,
                                                                const needle::NeedleHit& hit, double wedgeAxial,
                                                                const ContactStep& cs) {
  const RigidNeedle& nd = needle_;
  const int d = dim_;
  double* ft = &needleFt_[static_cast<std::size_t>(n) * 3];
  const double k = needleContactStiffness(n, cs.dtPen);
  const double fn = contact::penaltyForce(k, hit.depth);
  Vector3d f = fn * hit.normal;
  const double mu = hit.face == needle::NeedleFace::Tip ? nd.frictionTip : nd.wallFriction(n);
  recordNormalContact(n, 0, hit.normal, k, hit.depth, vb, mu);
  if (nd.path)
    for (int i = 0; i < 3; ++i) contactAxis_[static_cast<std::size_t>(n) * 3 + i] = pose.axis[i];
  contactWedge_[n] = wedgeAxial;
  contactTip_[n] = hit.face == needle::NeedleFace::Tip;
  if (mu > 0) {
    const Vector3d t = contact::stickSpringFriction(Vector3d(ft[0], ft[1], ft[2]), hit.normal, v - vb,
                                                    contact::massPenalty(cs.stick, mass_[n], cs.dtPen) * cs.dtStep,
                                                    mu * fn);
    ft[0] = t[0], ft[1] = t[1], ft[2] = t[2];
    f += t;
    for (int i = 0; i < d; ++i) fconFriction_[static_cast<std::size_t>(n) * d + i] = t[i];
  } else {
    ft[0] = ft[1] = ft[2] = 0;
  }
  for (int i = 0; i < d; ++i) {
    fcon_[static_cast<std::size_t>(n) * d + i] += f[i];
    fconNeedle_[static_cast<std::size_t>(n) * d + i] = f[i];
  }
  return {f, fn, contact::penaltyEnergy(k, hit.depth)};
}

void ExplicitSolver::needleContactForces(const ContactStep& cs) {
  RigidNeedle& nd = needle_;
  const Vector3d base = nd.pose.tip - nd.shape.length * nd.pose.axis;
  double fx = 0, fy = 0, fz = 0, mx = 0, my = 0, mz = 0, tx = 0, ty = 0, tz = 0, fnSum = 0, maxPen = 0, ePen = 0;
  double drv = 0;  // path needle: reaction along the local tangents
  int count = 0;
  std::fill(fconNeedle_.begin(), fconNeedle_.end(), 0.0);
  std::fill(fconFriction_.begin(), fconFriction_.end(), 0.0);
#pragma omp parallel for schedule(static) if (nnode_ >= kParallelMin) reduction(+ : fx, fy, fz, mx, my, mz, tx, ty, tz, fnSum, count, ePen, drv) \
    reduction(max : maxPen)
  for (int n = 0; n < nnode_; ++n) {
    Vector3d x, v;
    nodeState(n, x, v);
    double* ft = &needleFt_[static_cast<std::size_t>(n) * 3];
    // a needle following a path: the straight needle in the frame of x's nearest station (path_needle.hpp),
    // its surface moving with the insertion speed along the local tangent
    needle::NeedlePose pose = nd.pose;
    if (nd.path && !pathPoseNear(nd, x, pose)) {  // beyond the needle's reach across its path
      ft[0] = ft[1] = ft[2] = 0;
      continue;
    }
    const Vector3d vb = nd.path ? Vector3d(nd.velocity * pose.axis) : needleSurfaceVelocity(nd, x);  // needle_motion.cpp
    double wedgeAxial = 0.0;  // axial face force per unit lateral force on a wedged lip (reaction only)
    needle::NeedleHit hit = needleHit(n, x, pose, wedgeAxial);
    if (!hit.inside) {
      ft[0] = ft[1] = ft[2] = 0;
      needleK_[n] = 0.0;  // the contact episode ends
      continue;
    }
    const NeedleNodeForce c = needleNodeForce(n, v, vb, pose, hit, wedgeAxial, cs);
    const double fn = c.normal;
    Vector3d f = c.force;
    ePen += c.energy;
    // reaction on the needle: -f at x; moment about the base centre. A wedged lip (above) feels
    // only the lateral part fn of the face force; the needle takes the whole face force, whose
    // axial part fn tan(face) makes the needle's work match the opening work at the face.
    if (wedgeAxial != 0.0) f += fn * wedgeAxial * pose.axis;
    Vector3d r = x - base, m = r.cross(-f);
    fx -= f[0], fy -= f[1], fz -= f[2];
    drv -= f.dot(pose.axis);
    mx += m[0], my += m[1], mz += m[2];
    if (hit.face == needle::NeedleFace::Tip) tx -= f[0], ty -= f[1], tz -= f[2];
    fnSum += fn;
    ++count;
    maxPen = std::max(maxPen, hit.depth);
  }
  // the forces the next step applies: completed by normalContactCorrection (contact_normal.cpp)
  needleStage_ = {Vector3d(fx, fy, fz), Vector3d(mx, my, mz), Vector3d(tx, ty, tz), fnSum, drv};
  nd.nodesInContact = count;
  nd.maxPenetration = maxPen;
  en_.penaltyEnergy = ePen;
  if (maxPen > penetrationTol_) failNeedlePenetration(maxPen);
}

void ExplicitSolver::computeStableStep() {
  double dt = opt_.cfl * dtStable_;
  if (cohOmega2_ > 0) dt = opt_.cfl / std::sqrt(1.0 / (dtStable_ * dtStable_) + 0.25 * cohOmega2_);
  if (opt_.maxTimeStep > 0) dt = std::min(dt, opt_.maxTimeStep);
  if (dtInitial_ == 0.0) dtInitial_ = dt;
  if (!(dt > opt_.minTimeStepRatio * dtInitial_)) {
    int e = static_cast<int>(std::min_element(dtElem_.begin(), dtElem_.end()) - dtElem_.begin());
    fail("stable time step collapsed to " + fmtNum(dt) + " s (" + fmtNum(dt / dtInitial_) + " of the initial " +
             fmtNum(dtInitial_) + " s): a badly distorted element",
         elementWhere(e),
         "Remedy: refine or regrade the mesh near the needle, lower the speed, or use a frictionless tip");
  }
  dt_ = dt;
}

// Forces and stable step at the initial state (initial displacement or velocity may have been set).
void ExplicitSolver::startFirstStep() {
  const double dtKeep = dt_;
  elementForces(0.0);
  gatherForces();
  computeStableStep();
  if (dtKeep > 0.0 && dtKeep < dt_) dt_ = dtKeep;  // a first step shortened by advanceTo
  double ke = 0;
  for (std::size_t k = 0; k < u_.size(); ++k) ke += 0.5 * mass_[k / dim_] * vHalf_[k] * vHalf_[k];
  en_.kinetic = en_.kinetic0 = ke;
}

// Tied seam pairs move together: equal and opposite tie forces give both the pair's common
// acceleration (they do no work since the velocities agree); a pair the tip's leading point reached is released.
void ExplicitSolver::tieForces(double alpha) {
  const int d = dim_;
  if (hasNeedle_) {
    // the leading point of the tip: the sharp point of a bevel, the apex of a cone
    const auto& nd = needle_;
    Vector3d lead = nd.pose.tip;
    if (nd.shape.tip == TipType::Bevel) lead -= nd.shape.radius * nd.pose.bevelSide;
    for (std::size_t t = 0; t < tieA_.size(); ++t) {
      if (!tieOn_[t]) continue;
      Vector3d x = Vector3d::Zero();
      for (int i = 0; i < d; ++i) x[i] = mesh_.X[static_cast<std::size_t>(tieA_[t]) * d + i] + u_[static_cast<std::size_t>(tieA_[t]) * d + i];
      if ((x - lead).dot(nd.pose.axis) < releaseDistance_) tieOn_[t] = 0;
    }
  }
  std::fill(ftie_.begin(), ftie_.end(), 0.0);
  for (std::size_t t = 0; t < tieA_.size(); ++t) {
    if (!tieOn_[t]) continue;
    const int a = tieA_[t], b = tieB_[t];
    const double ma = mass_[a], mb = mass_[b];
    for (int i = 0; i < d; ++i) {
      const std::size_t ka = static_cast<std::size_t>(a) * d + i, kb = static_cast<std::size_t>(b) * d + i;
      double fa = fext_[ka] - fint_[ka] + fcon_[ka] - alpha * ma * vHalf_[ka] + (coh_.empty() ? 0.0 : fcoh_[ka]);
      double fb = fext_[kb] - fint_[kb] + fcon_[kb] - alpha * mb * vHalf_[kb] + (coh_.empty() ? 0.0 : fcoh_[kb]);
      double tf = ma * (fa + fb) / (ma + mb) - fa;
      ftie_[ka] = tf;
      ftie_[kb] = -tf;
    }
  }
}

void ExplicitSolver::checkHourglassing() const {
  int e = static_cast<int>(std::max_element(hgStrain_.begin(), hgStrain_.end()) - hgStrain_.begin());
  if (hgStrain_[e] > opt_.hourglassStrainLimit)
    fail("hourglassing: zig-zag (hourglass) strain " + fmtNum(hgStrain_[e]) + " exceeds the limit " +
             fmtNum(opt_.hourglassStrainLimit),
         elementWhere(e),
         "Remedy: refine the mesh under the load, raise model.explicit.hourglass, or use tri3/tet4 elements");
}

void ExplicitSolver::step() {
  const std::size_t ndof = u_.size();
  if (steps_ == 0) startFirstStep();
  const double dt = dt_;
  const double dtAvg = steps_ == 0 ? 0.5 * dt : 0.5 * (dtPrev_ + dt);
  const double alpha = opt_.damping;
  normalContactCorrection(dt, dtAvg);
  if (!tieA_.empty()) tieForces(alpha);
  const bool ties = !tieA_.empty(), coh = !coh_.empty();
  double ke = 0, keMid = 0, wInt = 0, wExt = 0, wCon = 0, wDamp = 0, wCoh = 0, wConN = 0, dFric = 0;
  const int d = dim_;
  double vbd[3] = {0, 0, 0};  // needle velocity
  if (hasNeedle_) {
    for (int i = 0; i < d; ++i) vbd[i] = needle_.velocity * needle_.pose.axis[i];
    // work of the needle over the step: minus its reaction times its displacement (a path needle: the
    // reaction along the local tangents, each contact point moving with the speed along its tangent)
    if (needle_.path) en_.needleWork -= needle_.driveForce * needle_.velocity * dt;
    else en_.needleWork -= needle_.force.dot(needle_.velocity * needle_.pose.axis) * dt;
  }
  const bool nee = hasNeedle_;
  const double* pax = contactAxis_.empty() ? nullptr : contactAxis_.data();  // path needle: local axes
  const double vNee = hasNeedle_ ? needle_.velocity : 0.0;
#pragma omp parallel for schedule(static) if (ndof >= 2 * kParallelMin) reduction(+ : ke, keMid, wInt, wExt, wCon, wDamp, wCoh, wConN, dFric)
  for (std::size_t k = 0; k < ndof; ++k) {
    const double m = mass_[k / d];
    const double vOld = vHalf_[k];
    const double fd = -alpha * m * vOld;
    const double fc = coh ? fcoh_[k] : 0.0;
    const double ftot = fext_[k] - fint_[k] + fcon_[k] + fd + fc + (ties ? ftie_[k] : 0.0);
    const int grp = dofGroup_[k];
    double vNew, r = 0.0;
    if (grp >= 0) {
      vNew = groupVelocity_[grp];
      r = m * (vNew - vOld) / dtAvg - ftot;
    } else {
      vNew = vOld + dtAvg * ftot / m;
    }
    react_[k] = r;
    // Work over the step with the mid-point velocity: exact energy identity of central differences.
    const double dw = 0.5 * (vOld + vNew) * dtAvg;
    wInt += fint_[k] * dw;
    wExt += (fext_[k] + r) * dw;
    wCon += fcon_[k] * dw;
    wDamp += fd * dw;
    wCoh -= fc * dw;
    if (nee) {
      wConN += fconNeedle_[k] * dw;
      const double vb = pax ? vNee * pax[(k / d) * 3 + k % d] : vbd[k % d];
      dFric -= fconFriction_[k] * (dw - vb * dtAvg);  // friction force times slip
    }
    ke += 0.5 * m * vNew * vNew;
    keMid += 0.125 * m * (vOld + vNew) * (vOld + vNew);
    vHalf_[k] = vNew;
    u_[k] += dt * vNew;
  }
  if (!std::isfinite(ke)) {
    std::size_t k = 0;
    while (k < ndof && std::isfinite(vHalf_[k])) ++k;
    fail("non-finite velocity at node " + std::to_string(k / d), "",
         "Remedy: lower model.explicit.cfl or the mass scaling; check the material parameters");
  }
  for (double& r : groupReaction_) r = 0.0;
  for (std::size_t k = 0; k < ndof; ++k)
    if (dofGroup_[k] >= 0) groupReaction_[dofGroup_[k]] += react_[k];
  en_.kinetic = ke;
  en_.kineticMid = keMid;
  en_.internal += wInt;
  en_.externalWork += wExt;
  en_.contactWork += wCon;
  en_.dampingWork += wDamp;
  en_.cohesiveWork += wCoh;
  en_.needleContactWork += wConN;
  en_.frictionDissipation += dFric;
  time_ += dt;
  dtPrev_ = dt;
  ++steps_;
  // Rigid bodies move with their velocities.
  if (hasNeedle_) advanceNeedle(needle_, dt);
  for (auto& pl : planes_) pl.point += dt * pl.velocity;
  // Forces at the new configuration.
  elementForces(dt);
  gatherForces();
  contactForces(dt);
  cohesiveForces();
  if (nhg_ > 0 && (steps_ & 15) == 0) checkHourglassing();
  computeStableStep();
}

void ExplicitSolver::elementForces(double dtStep) {
  switch (mesh_.type) {
    case ElementType::Quad4: internalForces<4, 2>(dtStep); break;
    case ElementType::Tri3: internalForces<3, 2>(dtStep); break;
    case ElementType::Hex8: internalForces<8, 3>(dtStep); break;
    case ElementType::Tet4: internalForces<4, 3>(dtStep); break;
  }
}

void ExplicitSolver::setDisplacement(const std::vector<double>& u) {
  if (u.size() != u_.size()) throw Error("setDisplacement: size mismatch");
  u_ = u;
  elementForces(0.0);
  gatherForces();
}

void ExplicitSolver::advanceTo(double t) {
  while (time_ < t * (1 - 1e-12) - 1e-300) {
    if (time_ + dt_ > t) dt_ = t - time_;
    step();
  }
}

Matrix3d ExplicitSolver::deformationGradient(int e) const {
  Matrix3d F = Matrix3d::Identity();
  const int* cn = &mesh_.conn[static_cast<std::size_t>(e) * npe_];
  const double* g = &grad0_[static_cast<std::size_t>(e) * npe_ * dim_];
  for (int a = 0; a < npe_; ++a)
    for (int i = 0; i < dim_; ++i)
      for (int j = 0; j < dim_; ++j) F(i, j) += u_[static_cast<std::size_t>(cn[a]) * dim_ + i] * g[a * dim_ + j];
  return F;
}

void ExplicitSolver::cellFields(std::vector<double>& cauchy, std::vector<double>& mises,
                                std::vector<double>& logStrain, std::vector<double>& Jout) const {
  cauchy.assign(static_cast<std::size_t>(nel_) * 6, 0.0);
  logStrain.assign(static_cast<std::size_t>(nel_) * 6, 0.0);
  mises.assign(nel_, 0.0);
  Jout.assign(nel_, 1.0);
#pragma omp parallel for schedule(static)
  for (int e = 0; e < nel_; ++e) {
    Matrix3d F = deformationGradient(e);
    double J = F.determinant();
    Jout[e] = J;
    Voigt sv;
    for (int k = 0; k < 6; ++k) sv[k] = spk2_[static_cast<std::size_t>(e) * 6 + k];
    Matrix3d sig = J > 0 ? Matrix3d(F * fromVoigt(sv) * F.transpose() / J) : Matrix3d::Zero();
    if (!anpDp_.empty()) sig += anpDp_[e] * Matrix3d::Identity();  // nodal pressure (nodal_pressure.cpp)
    Eigen::SelfAdjointEigenSolver<Matrix3d> es(F * F.transpose());
    Eigen::Vector3d lg = es.eigenvalues().cwiseMax(1e-300).array().log() * 0.5;
    Matrix3d eps = es.eigenvectors() * lg.asDiagonal() * es.eigenvectors().transpose();
    Voigt s = toVoigt(sig), ls = toVoigt(eps);
    for (int k = 0; k < 6; ++k) {
      cauchy[static_cast<std::size_t>(e) * 6 + k] = std::isfinite(s[k]) ? s[k] : 0.0;
      logStrain[static_cast<std::size_t>(e) * 6 + k] = std::isfinite(ls[k]) ? ls[k] : 0.0;
    }
    double vm = std::sqrt(0.5 * ((s[0] - s[1]) * (s[0] - s[1]) + (s[1] - s[2]) * (s[1] - s[2]) +
                                 (s[2] - s[0]) * (s[2] - s[0])) +
                          3 * (s[3] * s[3] + s[4] * s[4] + s[5] * s[5]));
    mises[e] = std::isfinite(vm) ? vm : 0.0;
  }
}

}  // namespace needlesim::explicit_fe
