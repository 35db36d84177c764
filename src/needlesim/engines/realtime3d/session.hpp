#pragma once
// Real-time session of the 3D needle insertion model: the thesis model (seed 003 sections
// 3.1-3.5) on a tetrahedral block (tissue.hpp) with the needle bending in two planes.
// Per step the tissue predicts its path displacements (3 per path point: t, n, b), the
// shared shaft coupling (engines/realtime/shaft_coupling.hpp: lateral ties in n and b,
// axial stick or Karnopp slip, eq 3.23) is solved on the coupled nodes, and the tissue
// commits the path loads. Tip forces (engines/realtime/tip_forces.hpp): pre-puncture
// stiffness per layer boundary (eq 3.16), cutting (eq 3.24), and the bevel's transverse load
// Q = ratio F_cut towards -bevelSide(roll) (seed 002 tip loads, needle/insertion_frame.hpp),
// which turns with the needle's roll, so a bevel flip steers the needle in 3D.
// With tissue.follow_tip the path follows the channel the tip cuts: the tip advances along its
// heading, which turns towards the bevel (-bevelSide) at the kinematic bevel-tip curvature
// (Webster et al. 2006, seed 002 sections 1 and 5.1) in the tissue's reference frame; each path
// point is placed on that channel when the tip reaches its depth and holds the shaft there,
// moved with the tissue (ShaftCoupling::setChannel). The tip is the channel's end, moved with
// the tissue.
// step() allocates nothing while dt stays the same, and is deterministic.
#include <Eigen/Core>
#include <vector>

#include "needlesim/engines/realtime/needle_settings.hpp"
#include "needlesim/engines/realtime/shaft_coupling.hpp"
#include "needlesim/engines/realtime3d/tissue.hpp"
#include "needlesim/needle/insertion_frame.hpp"

namespace needlesim::realtime3d {

using realtime::LayerForces;
using realtime::NeedleConfig;
using realtime::Phase;

// Tissue, needle, forces, frame and step (engines/realtime/needle_settings.hpp).
using SessionConfig = realtime::SessionSettings<TissueConfig>;

// The thesis gelatin and needle (realtime2d::thesisGelatinConfig) on a block of
// nodesDepth x nodesLateral x nodesLateral nodes; shared by tests and benchmarks.
SessionConfig gelatinBlockConfig(int nodesDepth, int nodesLateral, Backend backend = Backend::Auto);

// Needle base pose in the centred tissue frame.
struct BasePose {
  Eigen::Vector3d base = Eigen::Vector3d::Zero();  // m, needle base (hub)
  Eigen::Vector3d axis = Eigen::Vector3d::UnitX(); // needle direction base -> tip (normalised)
  double roll = 0.0;  // rad, turn about the axis from the frame's bevel orientation
};

struct StepResult {
  double time = 0.0;
  Eigen::Vector3d force = Eigen::Vector3d::Zero();   // N, tissue force on the needle
  Eigen::Vector3d torque = Eigen::Vector3d::Zero();  // N m, its moment about the base
  double axial_force = 0.0;     // N, resistance to insertion: -force . axial
  double stiffness_force = 0.0; // N, eq 3.16 part
  double cutting_force = 0.0;   // N, eq 3.24 part
  double friction_force = 0.0;  // N, shaft friction resisting insertion
  double lateral_force = 0.0;   // N, force . frame.lateral
  double out_of_plane_force = 0.0;  // N, force . frame.outOfPlane
  Eigen::Vector2d tip_load = Eigen::Vector2d::Zero();        // N, bevel load along lateral, outOfPlane
  Eigen::Vector3d tip_position = Eigen::Vector3d::Zero();    // m, centred tissue frame
  Eigen::Vector2d tip_deflection = Eigen::Vector2d::Zero();  // m, elastic, along lateral, outOfPlane
  double depth = 0.0;           // m, tip along the reference axis from the entry point
  Phase phase = Phase::Outside;
  int coupled = 0, sticking = 0;
  bool punctured_now = false;
  int iterations = 0;
};

class Session {
 public:
  explicit Session(const SessionConfig& cfg);
  // Pose putting the straight needle's tip at `depth` along the reference axis, the base
  // moved by (lateral, outOfPlane), the axis turned by `angle` in the insertion plane
  // (towards +lateral) and `tilt` out of it (towards +outOfPlane).
  BasePose poseAtDepth(double depth, double lateral = 0.0, double outOfPlane = 0.0, double angle = 0.0,
                       double tilt = 0.0, double roll = 0.0) const;
  const StepResult& step(const BasePose& pose, double dt);
  const StepResult& last() const { return out_; }

  const Tissue& tissue() const { return tissue_; }
  const TetMesh& mesh() const { return tissue_.mesh(); }
  const Eigen::VectorXd& displacement() const { return tissue_.dynamics().displacement(); }  // 3 per node
  // The displacement for a reader in another thread (realtime::TissueDynamics::saveDisplacement):
  // a cheap copy of its state here, the full field (3 per node) from it there, while this steps.
  void saveDisplacement(realtime::DisplacementState& state) const { tissue_.dynamics().saveDisplacement(state); }
  void displacementFrom(const realtime::DisplacementState& state, Eigen::VectorXd& u) const {
    tissue_.dynamics().displacementFrom(state, u);
  }
  // Needle centre line from base to tip, `count` points (>= 2) into out (3 x count), centred frame.
  void needleShape(int count, Eigen::Matrix3Xd& out) const;
  // Elastic deflection (lateral, outOfPlane) of the needle at arc length sigma from the base.
  Eigen::Vector2d needleDeflection(double sigma) const;
  // The needle-tissue coupling of the last step (coupled nodes, contact lengths, friction status).
  const realtime::ShaftCoupling& shaft() const { return shaft_; }
  const SessionConfig& config() const { return cfg_; }
  const Eigen::Vector3d& cornerShift() const { return shift_; }  // centred -> mesh coordinates
  double exitDepth() const { return s_exit_; }
  // path follow_tip: the tissue's displacement at the channel's end (its last coupled point's);
  // the tip is the channel's end (in the tissue's reference frame) moved by it.
  Eigen::Vector3d tipDisplacement() const;

 private:
  using Motion = realtime::AxialMotion;
  Motion moveBase(const BasePose& pose, double dt);
  void cutChannel(const BasePose& pose, Motion& mo);
  void reportLoads(double F1, double Fc, StepResult& o);
  std::vector<realtime::Membrane> membranesOf() const;
  realtime::ShaftSettings shaftSettings() const;
  std::size_t layerAt(double x, double tolerance) const;
  double cuttingAt(double s_tip) const;

  SessionConfig cfg_;
  Eigen::Vector3d shift_, entry_, t0_, n0_, b0_;
  Tissue tissue_;
  double L_ = 0.0, s_entry_ = 0.0, s_exit_ = 0.0;
  std::vector<double> path_s_;
  realtime::NeedleLine nl_;
  Eigen::Vector3d axis_ = Eigen::Vector3d::UnitX();
  double sB_prev_ = 0.0, time_ = 0.0;
  bool started_ = false;
  // follow_tip: the channel's end and heading (reference frame), the points placed on it so far
  Eigen::Vector3d cut_ = Eigen::Vector3d::Zero(), heading_ = Eigen::Vector3d::UnitX();
  bool cutting_ = false;
  int placed_ = 0;
  realtime::TipForces tip_;
  realtime::ShaftCoupling shaft_;
  StepResult out_;
};

}  // namespace needlesim::realtime3d
