#pragma once
// Real-time session of the 2D FE needle insertion model (seed 003 sections
// 3.1-3.5): linear elastic tissue (tissue.hpp), an Euler-Bernoulli needle
// clamped at its base (needle/beam_element.hpp influence functions), the needle-tissue coupling on the path nodes
// (eqs 3.18-3.21, with the modified local constraints of Gao et al. 2016, seed
// 003 ref 16) and the lumped forces of section 3.2: pre-puncture stiffness
// (eq 3.16), constant cutting (eq 3.24) and modified Karnopp friction (eq 3.23).
//
// Per step the tissue predicts its path displacements, a small SPD system on the
// coupled nodes (lateral ties + axial stick or implicit slip) is solved by an
// active set, and the tissue commits the resulting path loads. step() allocates
// nothing as long as dt stays the same (a new dt refactorises) and is deterministic.
#include <Eigen/Core>
#include <vector>

#include "needlesim/engines/realtime/needle_settings.hpp"
#include "needlesim/engines/realtime/shaft_coupling.hpp"
#include "needlesim/engines/realtime/tip_forces.hpp"
#include "needlesim/engines/realtime2d/tissue.hpp"
#include "needlesim/forces/stiffness.hpp"
#include "needlesim/needle/insertion_frame.hpp"
#include "needlesim/scenario/scenario.hpp"

namespace needlesim::realtime2d {

using realtime::LayerForces;
using realtime::NeedleConfig;
using realtime::Phase;

// Tissue, needle, forces, frame (its in-plane parts) and step (engines/realtime/needle_settings.hpp).
using SessionConfig = realtime::SessionSettings<TissueConfig>;

// The thesis experiment (seed 003 section 5.1: 10 wt% gelatin friction and cutting,
// 18 G regular-wall steel needle, 100 mm free length, 30 deg bevel) on a mesh of
// nodesDepth x nodesLateral nodes; shared by tests and benchmarks.
SessionConfig thesisGelatinConfig(int nodesDepth, int nodesLateral, Backend backend = Backend::Auto);

// Positions of the session's interface (poses, tip, needle shape, entry point) are in the
// centred tissue frame (origin at the centre of the entry face); the mesh's own node
// coordinates start at its corner: mesh point = centred point + cornerShift().
struct BasePose {
  double x = 0.0, y = 0.0;  // m, needle base (hub) in the centred tissue frame
  double angle = 0.0;       // rad, needle axis from +x (depth direction)
  // rad, turn of the needle about its axis from the frame's bevel orientation: the tissue
  // pushes the tip towards -bevelSign(roll) lateral (frame.bevelSign).
  double roll = 0.0;
};

struct StepResult {
  double time = 0.0;
  Eigen::Vector2d force = Eigen::Vector2d::Zero();  // N, total force of the tissue on the needle
  double torque = 0.0;          // N m, moment of that force about the base (+z)
  double axial_force = 0.0;     // N, resistance to insertion: -force . axis
  double stiffness_force = 0.0; // N, eq 3.16 part (axial)
  double cutting_force = 0.0;   // N, eq 3.24 part (axial)
  double friction_force = 0.0;  // N, friction on the shaft resisting insertion
  double lateral_force = 0.0;   // N, tissue force on the needle along frame.lateral (shaft + tip load)
  double tip_load = 0.0;        // N, transverse bevel load (along frame.lateral)
  Eigen::Vector2d tip_position = Eigen::Vector2d::Zero();  // m, centred tissue frame
  double tip_angle = 0.0;       // rad
  double tip_deflection = 0.0;  // m, elastic tip deflection along frame.lateral from the straight needle
  double depth = 0.0;           // m, tip position along the reference axis from the entry point
  Phase phase = Phase::Outside;
  int coupled = 0;              // coupled tissue nodes
  int sticking = 0;             // of which sticking axially
  bool punctured_now = false;
  int iterations = 0;           // active-set iterations
};

class Session {
 public:
  explicit Session(const SessionConfig& cfg);

  // Base pose that puts the straight needle's tip at `depth` along the reference axis.
  BasePose poseAtDepth(double depth, double lateral = 0.0, double rotation = 0.0, double roll = 0.0) const;
  // Advances by dt with the base at `pose`; the returned reference stays valid until the next call.
  const StepResult& step(const BasePose& pose, double dt);
  const StepResult& last() const { return out_; }

  const Tissue& tissue() const { return tissue_; }
  const Mesh& mesh() const { return tissue_.mesh(); }
  const Eigen::VectorXd& displacement() const { return tissue_.displacement(); }  // 2 per node
  // The displacement for a reader in another thread (realtime::TissueDynamics::saveDisplacement):
  // a cheap copy of its state here, the full field (2 per node) from it there, while this steps.
  void saveDisplacement(realtime::DisplacementState& state) const { tissue_.dynamics().saveDisplacement(state); }
  void displacementFrom(const realtime::DisplacementState& state, Eigen::VectorXd& u) const {
    tissue_.dynamics().displacementFrom(state, u);
  }
  // Needle centre line from base to tip, `count` points (>= 2) into `out` (2 x count).
  void needleShape(int count, Eigen::Matrix2Xd& out) const;
  // Lateral elastic deflection (+n) of the needle at arc length sigma from the base.
  double needleDeflection(double sigma) const;
  // The needle-tissue coupling of the last step (coupled nodes, contact lengths, friction status).
  const realtime::ShaftCoupling& shaft() const { return shaft_; }
  const SessionConfig& config() const { return cfg_; }
  const Eigen::Vector2d& entryPoint() const { return entry_; }   // centred tissue frame
  const Eigen::Vector2d& cornerShift() const { return shift_; }  // centred -> mesh coordinates
  double exitDepth() const { return s_exit_; }
  double entryDepth() const { return s_entry_; }  // where the axis meets the tissue (imported mesh: its boundary)

 private:
  using Motion = realtime::AxialMotion;
  Motion moveBase(const BasePose& pose, double dt);
  void reportLoads(const BasePose& pose, double F1, double Fc, StepResult& o);
  std::vector<realtime::Membrane> membranesOf() const;
  realtime::ShaftSettings shaftSettings() const;
  double nodeDepth(int pathNode) const;
  std::size_t layerAt(double x, double tolerance) const;
  double cuttingAt(double s_tip) const;

  SessionConfig cfg_;
  Eigen::Vector2d shift_, entry_, t0_, n0_;
  double theta0_ = 0.0;
  Tissue tissue_;
  double EI_ = 0.0, L_ = 0.0, s_entry_ = 0.0, s_exit_ = 0.0;
  int P_ = 0;  // path nodes
  // Needle state of the current step.
  double sB_ = 0.0, dB_ = 0.0, phi_ = 0.0, tanphi_ = 0.0, cosphi_ = 1.0, Q_ = 0.0;
  double sB_prev_ = 0.0;
  bool started_ = false;
  double time_ = 0.0;
  realtime::TipForces tip_;        // membranes (the entry face first) and cutting
  realtime::ShaftCoupling shaft_;  // lateral ties and Karnopp friction on the coupled nodes
  StepResult out_;
};

}  // namespace needlesim::realtime2d
