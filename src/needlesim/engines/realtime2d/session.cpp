#include "needlesim/engines/realtime2d/session.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "needlesim/core/error.hpp"
#include "needlesim/needle/beam_element.hpp"

namespace needlesim::realtime2d {

using needle::cantileverDeflection;
using needle::cantileverSlope;

namespace {
// A coupled node is released only once it lies this far ahead of the tip, so a node
// dragged along right at the tip does not flicker between coupled and free.
constexpr double kReleaseGap = 1e-4;  // m
Eigen::Vector2d cornerShiftOf(const SessionConfig& c) {
  TissueSpec block;
  block.width = c.tissue.mesh.width;
  return needle::cornerShift(block).head<2>();
}
SessionConfig normalised(SessionConfig c) {
  // The refined line of the mesh runs through the entry point.
  c.tissue.mesh.path_y = c.frame.entry.y() + cornerShiftOf(c).y();
  if (c.friction.D_p <= 0.0) c.friction.D_p = c.friction.C_p;  // static limit defaults to dynamic
  if (c.friction.D_n <= 0.0) c.friction.D_n = c.friction.C_n;
  if (!(c.needle.EI > 0.0) || !(c.needle.length > 0.0))
    throw SolverError("realtime2d: the needle needs EI > 0 and length > 0");
  for (auto& L : c.layers) {
    if (L.friction.D_p <= 0.0) L.friction.D_p = L.friction.C_p;
    if (L.friction.D_n <= 0.0) L.friction.D_n = L.friction.C_n;
  }
  if (!(c.dt > 0.0)) throw SolverError("realtime2d: the time step must be > 0");
  // Newmark stability (seed 003 eqs 3.2-3.4): gamma < 1/2 amplifies every mode; beta below
  // (gamma + 1/2)^2 / 4 is only conditionally stable and is checked against the mesh in Tissue.
  if (c.tissue.newmark.gamma < 0.5)
    throw SolverError("realtime2d: Newmark gamma = " + std::to_string(c.tissue.newmark.gamma) +
                      " < 1/2 is unstable (negative numerical damping); use gamma >= 0.5");
  return c;
}
}  // namespace

Session::Session(const SessionConfig& cfg_in)
    : cfg_(normalised(cfg_in)),
      shift_(cornerShiftOf(cfg_)),
      entry_(cfg_.frame.entry.head<2>()),
      t0_(cfg_.frame.axial.head<2>()),
      n0_(cfg_.frame.lateral.head<2>()),
      theta0_(std::atan2(t0_.y(), t0_.x())),
      tissue_(cfg_.tissue, entry_ + shift_, t0_, cfg_.dt) {
  EI_ = cfg_.needle.EI;
  L_ = cfg_.needle.length;
  s_exit_ = (tissue_.mesh().length() - entry_.x()) / t0_.x();
  P_ = static_cast<int>(tissue_.path().size());
  const int D = 2 * P_;
  status_.assign(static_cast<std::size_t>(P_), Status::Stick);
  nodeFriction_.assign(static_cast<std::size_t>(P_), cfg_.friction);
  if (!cfg_.layers.empty())
    for (int i = 0; i < P_; ++i)  // the layer holding the node (by its depth x)
      nodeFriction_[static_cast<std::size_t>(i)] = cfg_.layers[layerAt(nodeDepth(i), 1e-12)].friction;
  placeMembranes();
  offset_.assign(static_cast<std::size_t>(P_), 0.0);
  sigma_.assign(static_cast<std::size_t>(P_), 0.0);
  ell_.assign(static_cast<std::size_t>(P_), 0.0);
  pos_.assign(static_cast<std::size_t>(P_), 0.0);
  lambda_.assign(static_cast<std::size_t>(P_), 0.0);
  idx_.assign(static_cast<std::size_t>(D), 0);
  fK_.setZero(D); f_.setZero(D); y_.setZero(D); rhs_.setZero(D); x_.setZero(D);
  H_.setZero(D, D);
}

double Session::nodeDepth(int i) const {
  return tissue_.mesh().nodes(0, tissue_.path()[static_cast<std::size_t>(i)].node);
}

std::size_t Session::layerAt(double x, double tolerance) const {
  std::size_t L = 0;
  while (L + 1 < cfg_.layers.size() && x > cfg_.layers[L].depth_end + tolerance) ++L;
  return L;
}

// The entry face and every inner layer boundary the axis crosses: eq 3.16 with the
// layer's E and nu acts on the path node at the boundary until its puncture threshold.
void Session::placeMembranes() {
  auto lawOf = [&](std::size_t L) {
    const auto& m = L < cfg_.tissue.layers.size() ? cfg_.tissue.layers[L].second : cfg_.tissue.material;
    return forces::StiffnessLaw{m.E, m.nu, cfg_.needle.bevel_angle, 0.5 * std::numbers::pi - std::abs(theta0_)};
  };
  membranes_.push_back({0.0, cfg_.puncture_force, lawOf(0), 0});
  const auto& path = tissue_.path();
  for (std::size_t L = 1; L < cfg_.layers.size(); ++L) {
    const double s = (cfg_.layers[L - 1].depth_end - entry_.x()) / t0_.x();
    if (!(s > 0.0) || !(s < s_exit_)) continue;
    int node = 0;
    for (int i = 1; i < P_; ++i)
      if (std::abs(path[static_cast<std::size_t>(i)].s - s) < std::abs(path[static_cast<std::size_t>(node)].s - s)) node = i;
    membranes_.push_back({s, cfg_.layers[L].puncture_force, lawOf(L), node});
  }
}

double Session::cuttingAt(double s_tip) const {
  if (cfg_.layers.empty()) return cfg_.cutting_force;
  return cfg_.layers[layerAt(entry_.x() + s_tip * t0_.x(), 0.0)].cutting_force;
}

BasePose Session::poseAtDepth(double depth, double lateral, double rotation, double roll) const {
  const Eigen::Vector2d b = entry_ + (depth - L_) * t0_ + lateral * n0_;
  return {b.x(), b.y(), theta0_ + rotation, roll};
}

double Session::needleDeflection(double sigma) const {
  double w = Q_ * cantileverDeflection(sigma, L_, EI_);
  for (int i = 0; i < k_; ++i) w -= lambda_[static_cast<std::size_t>(i)] * cantileverDeflection(sigma, sigma_[static_cast<std::size_t>(i)], EI_);
  return w;
}

double Session::needleLateralAt(double p) const {
  return rigidLateral(p) + needleDeflection((p - sB_) / cosphi_);
}

void Session::needleShape(int count, Eigen::Matrix2Xd& out) const {
  count = std::max(count, 2);
  if (out.cols() != count) out.resize(2, count);
  for (int c = 0; c < count; ++c) {
    const double sigma = L_ * c / (count - 1);
    const double ax = sB_ + sigma * cosphi_;
    const double lat = dB_ + sigma * std::sin(phi_) + needleDeflection(sigma);
    out.col(c) = entry_ + ax * t0_ + lat * n0_;
  }
}

// In-place Cholesky solve of the leading m x m block of H_ with rhs_ -> x_.
bool Session::solveSmall(int m) {
  double* A = H_.data();
  const Eigen::Index ld = H_.outerStride();
  for (int j = 0; j < m; ++j) {
    double d = A[j + j * ld];
    for (int k = 0; k < j; ++k) d -= A[j + k * ld] * A[j + k * ld];
    if (!(d > 0.0)) return false;
    d = std::sqrt(d);
    A[j + j * ld] = d;
    for (int i = j + 1; i < m; ++i) {
      double s = A[i + j * ld];
      for (int k = 0; k < j; ++k) s -= A[i + k * ld] * A[j + k * ld];
      A[i + j * ld] = s / d;
    }
  }
  for (int i = 0; i < m; ++i) {  // L z = rhs
    double s = rhs_[i];
    for (int k = 0; k < i; ++k) s -= A[i + k * ld] * x_[k];
    x_[i] = s / A[i + i * ld];
  }
  for (int i = m - 1; i >= 0; --i) {  // L^T x = z
    double s = x_[i];
    for (int k = i + 1; k < m; ++k) s -= A[k + i * ld] * x_[k];
    x_[i] = s / A[i + i * ld];
  }
  return true;
}

const StepResult& Session::step(const BasePose& pose, double dt) {
  tissue_.setTimeStep(dt);
  const Motion mo = moveBase(pose, dt);
  StepResult& o = out_;
  o = StepResult{};
  time_ += dt;
  o.time = time_;
  o.depth = mo.s_tip;
  tissue_.predict();
  fK_.setZero();
  const double F1 = pressMembrane(mo.s_tip, o);
  const double Fc = cutAtTip(mo);
  // The tissue pushes the bevel tip towards -bevelSide (needle/insertion_frame.hpp).
  const double Qnew = -tipLoadRatio() * Fc * cfg_.frame.bevelSign(pose.roll);
  coupleNodes(mo.s_tip);
  Q_ = Qnew;
  measureShaft(mo.s_tip);
  o.iterations = solveCoupling(mo, dt);
  tissue_.commit(f_);
  reportLoads(pose, F1, Fc, o);
  o.phase = phaseOf(mo, Fc);
  sB_prev_ = sB_;
  return o;
}

// Needle kinematics in the reference frame (entry point, axis t0, normal n0).
Session::Motion Session::moveBase(const BasePose& pose, double dt) {
  const Eigen::Vector2d d = Eigen::Vector2d(pose.x, pose.y) - entry_;
  sB_ = d.dot(t0_);
  dB_ = d.dot(n0_);
  phi_ = pose.angle - theta0_;
  cosphi_ = std::cos(phi_);
  tanphi_ = std::tan(phi_);
  if (!started_) { sB_prev_ = sB_; started_ = true; }
  const double ds = sB_ - sB_prev_;
  return {ds, ds / dt, sB_ + L_ * cosphi_};
}

// Phase A: the tip indents the next unpunctured layer boundary (eq 3.16, the layer's
// E and nu) until its puncture threshold; phase B: the load is released and the tissue
// relaxes. Returns the indentation force (0 once punctured).
double Session::pressMembrane(double s_tip, StepResult& o) {
  pressing_ = false;
  while (pending_ < membranes_.size() && s_tip > membranes_[pending_].s) {
    const Membrane& mb = membranes_[pending_];
    const double F1 = mb.law.force(s_tip - mb.s);
    if (F1 < mb.threshold) {
      pressing_ = true;
      fK_[2 * mb.node] += F1;  // axial load on the boundary node
      return F1;
    }
    o.punctured_now = true;
    if (pending_ == 0) front_ = s_tip;
    ++pending_;
  }
  return 0.0;
}

// Cutting (eq 3.24) only when the tip advances into uncut tissue; while resting at the
// front (|v| inside the static band) the cutting load is held, as in the lumped force
// model; retraction releases it. Split linearly between the path nodes around the tip.
double Session::cutAtTip(const Motion& mo) {
  const auto& path = tissue_.path();
  const double band = 0.5 * cfg_.friction.static_band;
  const double s_tip = mo.s_tip;
  const bool inside = entered() && !pressing_ && s_tip > 0.0 && s_tip < s_exit_;
  double Fc = 0.0;
  if (inside && mo.v_ax > -band && s_tip >= front_ - 1e-9) Fc = cuttingAt(s_tip);
  if (entered()) front_ = std::max(front_, std::min(s_tip, s_exit_));
  if (Fc > 0.0) {
    int k = 0;
    while (k + 1 < P_ && path[static_cast<std::size_t>(k + 1)].s <= s_tip) ++k;
    if (k + 1 < P_) {
      const double s0 = path[static_cast<std::size_t>(k)].s, s1 = path[static_cast<std::size_t>(k + 1)].s;
      const double w1 = std::clamp((s_tip - s0) / (s1 - s0), 0.0, 1.0);
      fK_[2 * k] += (1.0 - w1) * Fc;
      fK_[2 * k + 2] += w1 * Fc;
    } else {
      fK_[2 * k] += Fc;
    }
  }
  return Fc;
}

double Session::tipLoadRatio() const {
  return cfg_.needle.tip_load_ratio >= 0.0 ? cfg_.needle.tip_load_ratio : 1.0 / std::tan(cfg_.needle.bevel_angle);
}

// Coupled nodes: the path prefix the tip has passed (current axial positions), short of
// a layer boundary the tip is still pressing. A newly coupled node is tied at its
// current gap (no jump); nodes behind a retracting tip are released.
void Session::coupleNodes(double s_tip) {
  const auto& path = tissue_.path();
  const Eigen::VectorXd& pu = tissue_.pathU();
  const double reach = pressing_ ? std::min(s_tip, membranes_[pending_].s - 1e-9) : s_tip;
  int k = 0;
  if (entered() && s_tip > 0.0)
    while (k < P_ && path[static_cast<std::size_t>(k)].s + pu[2 * k] <= reach + (k < k_ ? kReleaseGap : 0.0)) ++k;
  for (int i = k_; i < k; ++i) {
    offset_[static_cast<std::size_t>(i)] = pu[2 * i + 1] - needleLateralAt(path[static_cast<std::size_t>(i)].s + pu[2 * i]);
    status_[static_cast<std::size_t>(i)] = Status::Stick;
  }
  for (int i = k; i < k_; ++i) lambda_[static_cast<std::size_t>(i)] = 0.0;
  k_ = k;
}

// Current axial positions of the coupled nodes, their tributary shaft lengths in contact
// (boundaries clamped to the tissue: 0 .. tip or exit face) and arc positions from the base.
void Session::measureShaft(double s_tip) {
  const auto& path = tissue_.path();
  const Eigen::VectorXd& pu = tissue_.pathU();
  const int k = k_;
  for (int i = 0; i < k; ++i) pos_[static_cast<std::size_t>(i)] = path[static_cast<std::size_t>(i)].s + pu[2 * i];
  const double top = std::min(s_tip, s_exit_);
  for (int i = 0; i < k; ++i) {
    const auto p = static_cast<std::size_t>(i);
    const double lo = i == 0 ? 0.0 : std::clamp(0.5 * (pos_[p - 1] + pos_[p]), 0.0, top);
    const double hi = i + 1 == k ? top : std::clamp(0.5 * (pos_[p] + pos_[p + 1]), 0.0, top);
    ell_[p] = std::max(hi - lo, 0.0);
    sigma_[p] = std::max((pos_[p] - sB_) / cosphi_, 0.0);
  }
}

// Active set on the axial status of each coupled node (eq 3.23), to a fixed point.
int Session::solveCoupling(const Motion& mo, double dt) {
  int it = 0;
  for (; it < cfg_.max_active_set_iterations; ++it) {
    addKnownLoads();
    const int m = assembleCoupling(mo, dt);
    if (!solveSmall(m)) throw SolverError("realtime2d: the coupling system is not positive definite");
    for (int a = 0; a < m; ++a) f_[idx_[static_cast<std::size_t>(a)]] += x_[a];
    if (!updateFrictionStatus(mo, dt)) break;
  }
  return it + 1;
}

// Known loads (press, cutting, held static friction, undamped slip) into f_, and the
// path displacement they give, y = u0 + S f_known.
void Session::addKnownLoads() {
  const auto& S = tissue_.pathCompliance();
  f_ = fK_;
  for (int i = 0; i < k_; ++i) {
    const auto st = status_[static_cast<std::size_t>(i)];
    const double l = ell_[static_cast<std::size_t>(i)];
    const auto& fr = nodeFriction_[static_cast<std::size_t>(i)];
    if (!(l > 1e-9)) continue;
    if (st == Status::HoldPos) f_[2 * i] += fr.D_p * l;
    if (st == Status::HoldNeg) f_[2 * i] -= fr.D_n * l;
    if (st == Status::SlipPos && !(fr.b_p * l > 1e-12)) f_[2 * i] += fr.C_p * l;
    if (st == Status::SlipNeg && !(fr.b_n * l > 1e-12)) f_[2 * i] -= fr.C_n * l;
  }
  y_ = tissue_.predictedPath();
  for (int l = 0; l < 2 * P_; ++l)
    if (f_[l] != 0.0) y_.noalias() += f_[l] * S.col(l);
}

// The SPD system on the unknown slots (all lateral ties, axial stick and damped slip):
// H_ = S + needle flexibility between the ties (eq 3.12), rhs_ from the constraints.
// Returns its size.
int Session::assembleCoupling(const Motion& mo, double dt) {
  const PathState ps = pathState();
  const auto& S = ps.S;
  const auto& c = ps.c;
  const Eigen::VectorXd &pu = ps.u, &pv = ps.v, &pa = ps.a;
  const double gam = ps.gamma;
  int m = 0;
  for (int i = 0; i < k_; ++i) {
    idx_[static_cast<std::size_t>(m++)] = 2 * i + 1;
    const auto st = status_[static_cast<std::size_t>(i)];
    const double l = ell_[static_cast<std::size_t>(i)];
    const auto& fr = nodeFriction_[static_cast<std::size_t>(i)];
    if (!(l > 1e-9)) continue;  // no shaft in contact (dragged out of the tissue): no axial load
    if (st == Status::Stick || (st == Status::SlipPos && fr.b_p * l > 1e-12) ||
        (st == Status::SlipNeg && fr.b_n * l > 1e-12))
      idx_[static_cast<std::size_t>(m++)] = 2 * i;
  }
  for (int a = 0; a < m; ++a) {
    const int ia = idx_[static_cast<std::size_t>(a)];
    const int na = ia / 2;
    for (int b = 0; b <= a; ++b) {
      const int ib = idx_[static_cast<std::size_t>(b)];
      double h = S(ia, ib);
      if (ia % 2 == 1 && ib % 2 == 1)  // needle flexibility between lateral ties (eq 3.12)
        h += cantileverDeflection(sigma_[static_cast<std::size_t>(na)], sigma_[static_cast<std::size_t>(ib / 2)], EI_);
      H_(a, b) = h;
      H_(b, a) = h;
    }
    const auto p = static_cast<std::size_t>(na);
    if (ia % 2 == 1) {  // lateral tie: u_n = needle lateral + offset
      rhs_[a] = rigidLateral(pos_[p]) + Q_ * cantileverDeflection(sigma_[p], L_, EI_) + offset_[p] - y_[ia];
    } else if (status_[p] == Status::Stick) {  // axial: moves with the needle
      rhs_[a] = pu[ia] + mo.ds - y_[ia];
    } else {  // implicit slip: mu = r - cc u (eq 3.23 slip branches, Newmark velocity)
      const auto& fr = nodeFriction_[p];
      const bool posv = status_[p] == Status::SlipPos;
      const double C = posv ? fr.C_p : -fr.C_n, b = posv ? fr.b_p : fr.b_n;
      const double e = pv[ia] + dt * (1.0 - gam) * pa[ia] - c.a1 * pu[ia] - dt * gam * (c.a2 * pv[ia] + c.a3 * pa[ia]);
      const double r = ell_[p] * (C + b * (mo.v_ax - e)), cc = ell_[p] * b * c.a1;
      H_(a, a) += 1.0 / cc;
      rhs_[a] = r / cc - y_[ia];
    }
  }
  return m;
}

// New path displacement and the status checks of the modified Karnopp law (eq 3.23):
// stick -> hold beyond the static limit D l, hold -> slip beyond the band, slip -> stick
// inside it. Returns whether any status changed.
bool Session::updateFrictionStatus(const Motion& mo, double dt) {
  const PathState ps = pathState();
  const auto& S = ps.S;
  const auto& c = ps.c;
  const Eigen::VectorXd& u0 = tissue_.predictedPath();
  const Eigen::VectorXd &pu = ps.u, &pv = ps.v, &pa = ps.a;
  const double gam = ps.gamma;
  const double band = 0.5 * cfg_.friction.static_band;
  bool changed = false;
  for (int i = 0; i < k_; ++i) {
    const auto p = static_cast<std::size_t>(i);
    const int ia = 2 * i;
    double un = u0[ia];
    for (int l = 0; l < 2 * P_; ++l)
      if (f_[l] != 0.0) un += S(ia, l) * f_[l];
    const double an = c.a0 * (un - pu[ia]) - c.a2 * pv[ia] - c.a3 * pa[ia];
    const double vn = pv[ia] + dt * ((1.0 - gam) * pa[ia] + gam * an);
    const double vrel = mo.v_ax - vn;
    const double Fa = ell_[p] > 0.0 ? f_[ia] / ell_[p] : 0.0;
    const auto& fr = nodeFriction_[p];
    Status next = status_[p];
    switch (status_[p]) {
      case Status::Stick:
        if (Fa > fr.D_p) next = Status::HoldPos;
        else if (Fa < -fr.D_n) next = Status::HoldNeg;
        break;
      case Status::HoldPos:
        if (vrel >= band) next = Status::SlipPos;
        else if (vrel <= 0.0) next = Status::Stick;
        break;
      case Status::HoldNeg:
        if (vrel <= -band) next = Status::SlipNeg;
        else if (vrel >= 0.0) next = Status::Stick;
        break;
      case Status::SlipPos:
        if (vrel < band) next = Status::Stick;
        break;
      case Status::SlipNeg:
        if (vrel > -band) next = Status::Stick;
        break;
    }
    if (next != status_[p]) { status_[p] = next; changed = true; }
  }
  return changed;
}

// Needle loads and outputs: the tissue pushes the needle with -f on each tie, and with
// the press, cutting and bevel loads at the tip.
void Session::reportLoads(const BasePose& pose, double F1, double Fc, StepResult& o) {
  Eigen::Vector2d F = Eigen::Vector2d::Zero();
  double T = 0.0, fric = 0.0;
  for (int i = 0; i < k_; ++i) {
    const auto p = static_cast<std::size_t>(i);
    lambda_[p] = f_[2 * i + 1];
    fric += f_[2 * i];
    if (status_[p] == Status::Stick) ++o.sticking;
  }
  for (int i = 0; i < k_; ++i) {
    const auto p = static_cast<std::size_t>(i);
    const Eigen::Vector2d Fi = -f_[2 * i] * t0_ - f_[2 * i + 1] * n0_;
    const Eigen::Vector2d r = (pos_[p] - sB_) * t0_ + (needleLateralAt(pos_[p]) - dB_) * n0_;
    F += Fi;
    T += r.x() * Fi.y() - r.y() * Fi.x();
  }
  const Eigen::Vector2d tipF = -(F1 + Fc) * t0_ + Q_ * n0_;
  const Eigen::Vector2d rt = L_ * cosphi_ * t0_ + (L_ * std::sin(phi_) + needleDeflection(L_)) * n0_;
  F += tipF;
  T += rt.x() * tipF.y() - rt.y() * tipF.x();
  o.force = F;
  o.torque = T;
  o.axial_force = -F.dot(t0_);
  o.stiffness_force = F1;
  o.cutting_force = Fc;
  o.friction_force = fric;
  o.lateral_force = F.dot(n0_);
  o.tip_load = Q_;
  o.tip_deflection = needleDeflection(L_);
  double slope = Q_ * L_ * L_ / (2.0 * EI_);
  for (int i = 0; i < k_; ++i) slope -= lambda_[static_cast<std::size_t>(i)] * cantileverSlope(L_, sigma_[static_cast<std::size_t>(i)], EI_);
  o.tip_angle = pose.angle + slope;
  o.tip_position = entry_ + o.depth * t0_ + (dB_ + L_ * std::sin(phi_) + o.tip_deflection) * n0_;
  o.coupled = k_;
}

Phase Session::phaseOf(const Motion& mo, double Fc) const {
  const double band = 0.5 * cfg_.friction.static_band;
  if (mo.s_tip <= 0.0) return Phase::Outside;
  if (!entered() || pressing_) return Phase::Pressing;
  if (mo.s_tip >= s_exit_) return Phase::Through;
  if (Fc > 0.0 && mo.v_ax >= band) return Phase::Cutting;
  return Phase::Inside;
}

SessionConfig thesisGelatinConfig(int nodesDepth, int nodesLateral, Backend backend) {
  SessionConfig c;
  c.tissue.mesh.nodes_depth = nodesDepth;
  c.tissue.mesh.nodes_lateral = nodesLateral;
  c.tissue.backend = backend;
  const double D = 1.27e-3, d = 0.838e-3;  // 18 G regular wall
  c.needle.EI = 200e9 * std::numbers::pi / 64 * (std::pow(D, 4) - std::pow(d, 4));
  c.needle.length = 0.1;
  c.needle.bevel_angle = std::numbers::pi / 6;
  c.friction.C_p = c.friction.C_n = 3.791;      // seed 003 section 5.1
  c.friction.b_p = c.friction.b_n = 285.053;
  c.friction.static_band = 1e-4;
  c.cutting_force = 0.04335;
  c.dt = 1e-3;
  return c;
}

}  // namespace needlesim::realtime2d
