#include "needlesim/engines/realtime2d/session.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "needlesim/core/error.hpp"
#include "needlesim/engines/realtime2d/imported_mesh.hpp"
#include "needlesim/needle/beam_element.hpp"

namespace needlesim::realtime2d {

namespace {
Eigen::Vector2d cornerShiftOf(const SessionConfig& c) {
  TissueSpec block;
  block.width = c.tissue.mesh.width;
  return needle::cornerShift(block).head<2>();
}
SessionConfig normalised(SessionConfig c) {
  // The refined line of the mesh runs through the entry point.
  c.tissue.mesh.path_y = c.frame.entry.y() + cornerShiftOf(c).y();
  realtime::checkSessionSettings(c, "realtime2d");
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
  if (const auto& g = cfg_.tissue.geometry) {
    s_entry_ = g->entry_depth;
    s_exit_ = exitAlongAxis(*g, entry_, t0_);
  } else {
    s_exit_ = (tissue_.mesh().length() - entry_.x()) / t0_.x();
  }
  P_ = static_cast<int>(tissue_.path().size());
  std::vector<double> path_s;
  for (const auto& p : tissue_.path()) path_s.push_back(p.s);
  tip_ = realtime::TipForces(membranesOf(), path_s, 2);
  shaft_ = realtime::ShaftCoupling(shaftSettings());
}

realtime::ShaftSettings Session::shaftSettings() const {
  realtime::ShaftSettings s{"realtime2d", 1, EI_, L_, {}, {}, cfg_.max_active_set_iterations, s_entry_};
  for (const auto& p : tissue_.path()) s.path_s.push_back(p.s);
  s.friction.assign(static_cast<std::size_t>(P_), cfg_.friction);
  if (!cfg_.layers.empty())
    for (int i = 0; i < P_; ++i)  // the layer holding the node (by its depth x)
      s.friction[static_cast<std::size_t>(i)] = cfg_.layers[layerAt(nodeDepth(i), 1e-12)].friction;
  return s;
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
std::vector<realtime::Membrane> Session::membranesOf() const {
  auto lawOf = [&](std::size_t L) {
    const auto& m = L < cfg_.tissue.layers.size() ? cfg_.tissue.layers[L].second : cfg_.tissue.material;
    return forces::StiffnessLaw{m.E, m.nu, cfg_.needle.bevel_angle, 0.5 * std::numbers::pi - std::abs(theta0_)};
  };
  std::vector<double> path_s;
  for (const auto& p : tissue_.path()) path_s.push_back(p.s);
  std::vector<realtime::Membrane> out{
      {s_entry_, cfg_.puncture_force, lawOf(0), realtime::TipForces::nearestNode(path_s, s_entry_)}};
  for (std::size_t L = 1; L < cfg_.layers.size(); ++L) {
    const double s = (cfg_.layers[L - 1].depth_end - entry_.x()) / t0_.x();
    if (!(s > 0.0) || !(s < s_exit_)) continue;
    out.push_back({s, cfg_.layers[L].puncture_force, lawOf(L), realtime::TipForces::nearestNode(path_s, s)});
  }
  return out;
}

double Session::cuttingAt(double s_tip) const {
  if (cfg_.layers.empty()) return cfg_.cutting_force;
  return cfg_.layers[layerAt(entry_.x() + s_tip * t0_.x(), 0.0)].cutting_force;
}

BasePose Session::poseAtDepth(double depth, double lateral, double rotation, double roll) const {
  const Eigen::Vector2d b = entry_ + (depth - L_) * t0_ + lateral * n0_;
  return {b.x(), b.y(), theta0_ + rotation, roll};
}

double Session::needleDeflection(double sigma) const { return shaft_.deflection(0, sigma); }

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

const StepResult& Session::step(const BasePose& pose, double dt) {
  tissue_.setTimeStep(dt);
  const Motion mo = moveBase(pose, dt);
  StepResult& o = out_;
  o = StepResult{};
  time_ += dt;
  o.time = time_;
  o.depth = mo.s_tip;
  tissue_.predict();
  Eigen::VectorXd& fK = shaft_.knownLoads();
  fK.setZero();
  const double F1 = tip_.press(mo.s_tip, fK, o.punctured_now);
  const double Fc = tip_.cut(mo, cuttingAt(mo.s_tip), 0.5 * cfg_.friction.static_band, s_exit_, fK);
  // The tissue pushes the bevel tip towards -bevelSide (needle/insertion_frame.hpp).
  const double Qnew = -cfg_.needle.tipLoadRatio() * Fc * cfg_.frame.bevelSign(pose.roll);
  realtime::NeedleLine nl{sB_, cosphi_, {dB_, 0.0}, {tanphi_, 0.0}, {Q_, 0.0}};
  shaft_.setNeedle(nl);  // the new pose with the last tip load: new nodes tie at their gap
  const auto& pu = tissue_.pathU();
  shaft_.couple(tip_.entered() && mo.s_tip > 0.0, tip_.reach(mo.s_tip), pu);
  Q_ = Qnew;
  nl.Q[0] = Q_;
  shaft_.setNeedle(nl);
  shaft_.measure(mo.s_tip, s_exit_, pu);
  o.iterations = shaft_.solve(tissue_.dynamics(), mo, dt);
  tissue_.commit(shaft_.loads());
  reportLoads(pose, F1, Fc, o);
  o.phase = realtime::phaseOf(tip_, mo, Fc, s_exit_, 0.5 * cfg_.friction.static_band);
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

// Needle loads and outputs: the tissue pushes the needle with -f on each tie, and with
// the press, cutting and bevel loads at the tip.
void Session::reportLoads(const BasePose& pose, double F1, double Fc, StepResult& o) {
  Eigen::Vector2d F = Eigen::Vector2d::Zero();
  double T = 0.0, fric = 0.0;
  const Eigen::VectorXd& f = shaft_.loads();
  const int k = shaft_.coupled();
  for (int i = 0; i < k; ++i) {
    const double fa = shaft_.shaftAxialLoad(i);  // the tip's press and cutting loads are added once, below
    fric += fa;
    if (shaft_.status(i) == realtime::FrictionStatus::Stick) ++o.sticking;
    const Eigen::Vector2d Fi = -fa * t0_ - f[2 * i + 1] * n0_;
    const double p = shaft_.position(i);
    const Eigen::Vector2d r = (p - sB_) * t0_ + (shaft_.lateralAt(0, p) - dB_) * n0_;
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
  o.tip_angle = pose.angle + shaft_.slope(0, L_);
  o.tip_position = entry_ + o.depth * t0_ + (dB_ + L_ * std::sin(phi_) + o.tip_deflection) * n0_;
  o.coupled = k;
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
  c.friction.D_p = c.friction.D_n = 3.791 + 285.053 * 0.5e-4;  // the continuous law (the scenario default)
  c.cutting_force = 0.04335;
  c.dt = 1e-3;
  return c;
}

}  // namespace needlesim::realtime2d
