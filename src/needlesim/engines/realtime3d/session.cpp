#include "needlesim/engines/realtime3d/session.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "needlesim/core/error.hpp"
#include "needlesim/engines/realtime2d/session.hpp"

namespace needlesim::realtime3d {

namespace {
Eigen::Vector3d cornerShiftOf(const SessionConfig& c) {
  TissueSpec block;
  block.length = c.tissue.block.length;
  block.width = c.tissue.block.width;
  block.height = c.tissue.block.height;
  return needle::cornerShift(block);
}
// The stretch of the reference axis in the tissue: from the entry face (or where the axis meets
// the imported geometry) to the far face (or where it leaves the geometry the last time).
double pathBegin(const SessionConfig& c) { return c.tissue.geometry ? c.tissue.geometry->entry_depth : 0.0; }
double pathEnd(const SessionConfig& c) {
  const Eigen::Vector3d t = c.frame.axial.normalized();
  if (const auto& g = c.tissue.geometry) return exitAlongAxis(*g, c.frame.entry, t);
  return (c.tissue.block.length - (c.frame.entry + cornerShiftOf(c)).x()) / t.x();
}
SessionConfig normalised(SessionConfig c) {
  // The refined line of the mesh runs through the entry point.
  const Eigen::Vector3d e = c.frame.entry + cornerShiftOf(c);
  c.tissue.block.path_y = e.y();
  c.tissue.block.path_z = e.z();
  realtime::checkSessionSettings(c, "realtime3d");
  return c;
}
}  // namespace

Session::Session(const SessionConfig& cfg_in)
    : cfg_(normalised(cfg_in)),
      shift_(cornerShiftOf(cfg_)),
      entry_(cfg_.frame.entry),
      t0_(cfg_.frame.axial.normalized()),
      n0_(cfg_.frame.lateral.normalized()),
      b0_(t0_.cross(n0_)),
      tissue_(cfg_.tissue, entry_ + shift_, t0_, n0_, cfg_.dt, pathBegin(cfg_), pathEnd(cfg_)) {
  L_ = cfg_.needle.length;
  s_entry_ = pathBegin(cfg_);
  s_exit_ = pathEnd(cfg_);
  for (const auto& p : tissue_.path()) path_s_.push_back(p.s);
  tip_ = realtime::TipForces(membranesOf(), path_s_, 3);
  shaft_ = realtime::ShaftCoupling(shaftSettings());
  nl_.sB = -L_;
}

std::size_t Session::layerAt(double x, double tolerance) const {
  std::size_t L = 0;
  while (L + 1 < cfg_.layers.size() && x > cfg_.layers[L].depth_end + tolerance) ++L;
  return L;
}

double Session::cuttingAt(double s_tip) const {
  if (cfg_.layers.empty()) return cfg_.cutting_force;
  return cfg_.layers[layerAt((entry_ + shift_).x() + s_tip * t0_.x(), 0.0)].cutting_force;
}

realtime::ShaftSettings Session::shaftSettings() const {
  realtime::ShaftSettings s{"realtime3d", 2, cfg_.needle.EI, L_, path_s_, {}, cfg_.max_active_set_iterations, s_entry_};
  for (const auto& p : tissue_.path()) {  // the layer holding the point (by its depth x)
    s.friction.push_back(cfg_.layers.empty() ? cfg_.friction : cfg_.layers[layerAt(p.X.x(), 1e-12)].friction);
    for (int c = 0; c < 3; ++c) s.interface_compliance.push_back(p.compliance[c]);
  }
  return s;
}

// The entry face and every inner layer boundary the axis crosses (eq 3.16, the layer's E, nu).
std::vector<realtime::Membrane> Session::membranesOf() const {
  const double theta = 0.5 * std::numbers::pi - std::acos(std::clamp(t0_.x(), -1.0, 1.0));
  auto lawOf = [&](std::size_t L) {
    const auto& m = L < cfg_.tissue.layers.size() ? cfg_.tissue.layers[L].second : cfg_.tissue.material;
    return forces::StiffnessLaw{m.E, m.nu, cfg_.needle.bevel_angle, theta};
  };
  std::vector<realtime::Membrane> out{{s_entry_, cfg_.puncture_force, lawOf(0), 0}};
  for (std::size_t L = 1; L < cfg_.layers.size(); ++L) {
    const double s = (cfg_.layers[L - 1].depth_end - (entry_ + shift_).x()) / t0_.x();
    if (!(s > 0.0) || !(s < s_exit_)) continue;
    out.push_back({s, cfg_.layers[L].puncture_force, lawOf(L), realtime::TipForces::nearestNode(path_s_, s)});
  }
  return out;
}

BasePose Session::poseAtDepth(double depth, double lateral, double outOfPlane, double angle, double tilt,
                              double roll) const {
  Eigen::Vector3d a = t0_ + std::tan(angle) * n0_ + std::tan(tilt) * b0_;
  a.normalize();
  const Eigen::Vector3d tip = entry_ + depth * t0_ + lateral * n0_ + outOfPlane * b0_;
  return {tip - L_ * a, a, roll};
}

Eigen::Vector2d Session::needleDeflection(double sigma) const {
  return {shaft_.deflection(0, sigma), shaft_.deflection(1, sigma)};
}

void Session::needleShape(int count, Eigen::Matrix3Xd& out) const {
  count = std::max(count, 2);
  if (out.cols() != count) out.resize(3, count);
  for (int c = 0; c < count; ++c) {
    const double sigma = L_ * c / (count - 1);
    const double p = nl_.sB + sigma * nl_.cosphi;
    out.col(c) = entry_ + p * t0_ + shaft_.lateralAt(0, p) * n0_ + shaft_.lateralAt(1, p) * b0_;
  }
}

// Needle kinematics in the reference frame (entry point, axis t0, lateral n0, b0).
Session::Motion Session::moveBase(const BasePose& pose, double dt) {
  const Eigen::Vector3d d = pose.base - entry_;
  const double na = pose.axis.norm();
  if (!(na > 0.0) || !std::isfinite(na)) throw SolverError("realtime3d: the needle axis of the pose must be nonzero");
  axis_ = pose.axis / na;
  const double c = axis_.dot(t0_);
  if (!(c > std::sqrt(0.5) - 1e-12))
    throw SolverError("realtime3d: the needle axis must stay within 45 degrees of the reference axis");
  nl_.sB = d.dot(t0_);
  nl_.cosphi = c;
  nl_.dB = {d.dot(n0_), d.dot(b0_)};
  nl_.tanphi = {axis_.dot(n0_) / c, axis_.dot(b0_) / c};
  if (!started_) { sB_prev_ = nl_.sB; started_ = true; }
  const double ds = nl_.sB - sB_prev_;
  return {ds, ds / dt, nl_.sB + L_ * c};
}

// follow_tip: outside the tissue the tip is the straight needle's; inside it advances by the
// inserted length along its heading, which turns towards -bevelSide(roll) at the channel
// curvature (kinematic bevel-tip model, Webster et al. 2006: d heading / d length = kappa d_perp).
// The path points whose depth the tip reaches (one spacing ahead, so before they couple) are
// placed on the line of its heading and embedded there; one outside the mesh stays on the axis.
void Session::cutChannel(const BasePose& pose, Motion& mo) {
  const double arc = mo.ds / nl_.cosphi;
  if (!cutting_) {
    cut_ = pose.base + L_ * axis_;
    heading_ = axis_;
    cutting_ = cut_.dot(t0_) - entry_.dot(t0_) > s_entry_;
  } else if (arc > 0.0) {
    Eigen::Vector3d d = -cfg_.frame.bevelSide(pose.roll);
    d -= d.dot(heading_) * heading_;
    cut_ += arc * heading_;
    if (d.norm() > 0.0) heading_ = (heading_ + cfg_.tissue.channel_curvature * arc * d.normalized()).normalized();
  } else {
    cut_ += arc * heading_;  // drawn back: along the channel's last heading
  }
  const double ax = (cut_ - entry_).dot(t0_), hx = heading_.dot(t0_);
  mo.s_tip = ax;
  const double ahead = cfg_.tissue.coupling_spacing;
  while (placed_ < static_cast<int>(path_s_.size()) && path_s_[static_cast<std::size_t>(placed_)] <= ax + ahead) {
    const Eigen::Vector3d p = cut_ + (path_s_[static_cast<std::size_t>(placed_)] - ax) / hx * heading_ - entry_;
    // embedded where it lies (the reference position: the channel is cut in the tissue's frame)
    if (tissue_.movePathPoint(static_cast<std::size_t>(placed_), p + entry_ + shift_, heading_)) {
      shaft_.setChannel(placed_, 0, p.dot(n0_));
      shaft_.setChannel(placed_, 1, p.dot(b0_));
    }
    ++placed_;
  }
}

// follow_tip: the tissue's displacement at the channel's end (its last coupled point's).
Eigen::Vector3d Session::tipDisplacement() const {
  const int k = shaft_.coupled();
  if (k == 0) return Eigen::Vector3d::Zero();
  const auto& pu = tissue_.dynamics().pathU();
  return pu[3 * (k - 1)] * t0_ + pu[3 * (k - 1) + 1] * n0_ + pu[3 * (k - 1) + 2] * b0_;
}

const StepResult& Session::step(const BasePose& pose, double dt) {
  tissue_.dynamics().setTimeStep(dt);
  Motion mo = moveBase(pose, dt);
  if (cfg_.tissue.follow_tip) cutChannel(pose, mo);
  StepResult& o = out_;
  o = StepResult{};
  time_ += dt;
  o.time = time_;
  o.depth = mo.s_tip;
  tissue_.dynamics().predict();
  Eigen::VectorXd& fK = shaft_.knownLoads();
  fK.setZero();
  const double F1 = tip_.press(mo.s_tip, fK, o.punctured_now);
  const double Fc = tip_.cut(mo, cuttingAt(mo.s_tip), 0.5 * cfg_.friction.static_band, s_exit_, fK);
  shaft_.setNeedle(nl_);  // the new pose with the last tip load: new nodes tie at their gap
  const auto& pu = tissue_.dynamics().pathU();
  shaft_.couple(tip_.entered() && mo.s_tip > 0.0, tip_.reach(mo.s_tip), pu);
  // The tissue pushes the bevel tip towards -bevelSide(roll) (needle/insertion_frame.hpp).
  const Eigen::Vector3d Q = -cfg_.needle.tipLoadRatio() * Fc * cfg_.frame.bevelSide(pose.roll);
  nl_.Q = {Q.dot(n0_), Q.dot(b0_)};
  shaft_.setNeedle(nl_);
  shaft_.measure(mo.s_tip, s_exit_, pu);
  o.iterations = shaft_.solve(tissue_.dynamics(), mo, dt);
  tissue_.dynamics().commit(shaft_.loads());
  reportLoads(F1, Fc, o);
  o.phase = realtime::phaseOf(tip_, mo, Fc, s_exit_, 0.5 * cfg_.friction.static_band);
  sB_prev_ = nl_.sB;
  return o;
}

// Needle loads: the tissue pushes the needle with -f on each tie, and with the press,
// cutting and bevel loads at the tip; moments about the base.
void Session::reportLoads(double F1, double Fc, StepResult& o) {
  const Eigen::VectorXd& f = shaft_.loads();
  const int k = shaft_.coupled();
  const Eigen::Vector3d base = entry_ + nl_.sB * t0_ + nl_.dB[0] * n0_ + nl_.dB[1] * b0_;
  auto at = [&](double p) { return entry_ + p * t0_ + shaft_.lateralAt(0, p) * n0_ + shaft_.lateralAt(1, p) * b0_; };
  Eigen::Vector3d F = Eigen::Vector3d::Zero(), T = Eigen::Vector3d::Zero();
  double fric = 0.0;
  for (int i = 0; i < k; ++i) {
    const double fa = shaft_.shaftAxialLoad(i);  // the tip's press and cutting loads are added once, below
    fric += fa;
    if (shaft_.status(i) == realtime::FrictionStatus::Stick) ++o.sticking;
    const Eigen::Vector3d Fi = -fa * t0_ - f[3 * i + 1] * n0_ - f[3 * i + 2] * b0_;
    F += Fi;
    T += (at(shaft_.position(i)) - base).cross(Fi);
  }
  const double s_tip = nl_.sB + L_ * nl_.cosphi;
  const Eigen::Vector3d tipF = -(F1 + Fc) * t0_ + nl_.Q[0] * n0_ + nl_.Q[1] * b0_;
  F += tipF;
  T += (at(s_tip) - base).cross(tipF);
  o.force = F;
  o.torque = T;
  o.axial_force = -F.dot(t0_);
  o.stiffness_force = F1;
  o.cutting_force = Fc;
  o.friction_force = fric;
  o.lateral_force = F.dot(n0_);
  o.out_of_plane_force = F.dot(b0_);
  o.tip_load = {nl_.Q[0], nl_.Q[1]};
  o.tip_deflection = needleDeflection(L_);
  o.tip_position = cfg_.tissue.follow_tip ? Eigen::Vector3d(cut_ + tipDisplacement()) : at(s_tip);
  o.coupled = k;
}

SessionConfig gelatinBlockConfig(int nodesDepth, int nodesLateral, Backend backend) {
  const auto thesis = realtime2d::thesisGelatinConfig(11, 11);
  SessionConfig c;
  c.needle = thesis.needle;
  c.friction = thesis.friction;
  c.cutting_force = thesis.cutting_force;
  c.dt = thesis.dt;
  c.tissue.material = {thesis.tissue.material.E, thesis.tissue.material.nu, thesis.tissue.material.density};
  c.tissue.block.nodes_depth = nodesDepth;
  c.tissue.block.nodes_lateral = c.tissue.block.nodes_height = nodesLateral;
  c.tissue.backend = backend;
  c.tissue.coupling_radius = 0.5 * 1.27e-3;  // 18 G
  return c;
}

}  // namespace needlesim::realtime3d
