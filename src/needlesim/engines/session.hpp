#pragma once
// The steppable session: an engine stepped by its caller (the C++ API's Session, needlesim
// serve and its haptic bridge through it, the Python Session) one commanded pose at a time.
// Each steppable engine implements it once (its adapter in its own folder) and names its opener
// in its one registration line (engines/registry.cpp, EngineInfo::open). Every step passes one guard, the same for every
// caller: finite arguments, dt > 0, only the axes the engine takes, a pose within the tissue's
// reach, and a tip that moves no more than the engine's step guard allows
// (kMaxTravelPerStep x StepPlan::spacing, engines/step_guard.hpp), from the first step on.
#include <Eigen/Core>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "needlesim/engines/realtime/tissue_dynamics.hpp"  // DisplacementState
#include "needlesim/engines/step_guard.hpp"
#include "needlesim/scenario/scenario.hpp"

namespace needlesim::engines {

// The base motion of one step.
struct SessionCommand {
  double depth = 0.0;     // m, tip along the reference axis from the entry point
  double lateral = 0.0;   // m, base offset across the axis
  double rotation = 0.0;  // rad, turn of the insertion plane
  double roll = 0.0;      // rad, bevel about the needle axis from the scenario's orientation
  double tilt = 0.0;      // rad, out of the insertion plane
  std::optional<double> velocity;  // m/s, the lumped model's tip velocity (default: depth change / dt)
};

// One step's outputs (forces.csv's quantities, docs/results.md).
struct SessionOutput {
  double depth = 0.0;               // m
  double axial_force = 0.0;         // N, resistance to insertion (stiffness + cutting + friction)
  double stiffness_force = 0.0;     // N, eq 3.16 part
  double cutting_force = 0.0;       // N, eq 3.24 part
  double friction_force = 0.0;      // N, eq 3.23 part
  double lateral_force = 0.0;       // N, along the frame's lateral direction (0 for lumped)
  double out_of_plane_force = 0.0;  // N, along the frame's outOfPlane (realtime3d)
  Eigen::Vector3d tip = Eigen::Vector3d::Zero();  // m, centred tissue frame (x depth, y, z)
  double tip_deflection = 0.0;      // m, elastic, along the frame's lateral direction
  double tip_deflection_z = 0.0;    // m, elastic, out of the plane (realtime3d)
  int phase = 0;                    // realtime::Phase / forces::Phase (same numbering)
  bool punctured_now = false;
  std::optional<double> torque;     // N m about the base (realtime2d)
  std::optional<double> tip_load;   // N, transverse bevel load (the FE engines)
};

// outside, pressing, cutting, inside, through.
std::string phaseName(int phase);

// The axes of SessionCommand an engine takes besides depth.
struct SessionAxes {
  bool lateral = false, rotation = false, roll = false, tilt = false;
  bool velocity = false;  // takes a given tip velocity
};

// Where a session's needle may go: the tip no deeper than the needle is long, the base offset
// across the axis and the angles that keep the needle's axis pointing into the tissue through
// its entry face.
struct SessionReach {
  double startDepth = 0.0;  // m, insertion.start_depth: where a session's needle starts
  double entryDepth = 0.0;  // m, tip depth where the axis meets the tissue
  double maxDepth = 0.0;    // m, needle.length
  double lateralLo = 0.0, lateralHi = 0.0;    // m, open range of the base offset
  double rotationLo = 0.0, rotationHi = 0.0;  // rad, open range of the in-plane turn
  double width = 0.0;                         // m, the entry face across the insertion plane
};
SessionReach reachOf(const Scenario& sc);

// The guard every step passes (InputError naming `Session.step(<argument>)`); the same
// messages for every caller.
class SessionGuard {
 public:
  SessionGuard(const Scenario& sc, const StepPlan& plan, SessionAxes axes);
  // `previous`: the depth of the previous step; none before the first (which starts at
  // insertion.start_depth; before the tissue the needle may be placed anywhere).
  void check(const SessionCommand& c, double dt, std::optional<double> previous) const;
  double maxTravel() const { return maxTravel_; }
  const SessionReach& reach() const { return reach_; }
  const SessionAxes& axes() const { return axes_; }

 private:
  void checkFinite(const SessionCommand& c, double dt) const;
  void checkAxes(const SessionCommand& c) const;
  void checkReach(const SessionCommand& c) const;
  void checkTravel(double depth, std::optional<double> previous) const;
  void checkVelocity(const SessionCommand& c, double dt, std::optional<double> previous) const;

  std::string engine_;
  SessionAxes axes_;
  SessionReach reach_;
  double maxTravel_ = 0.0;
  std::string travelLimit_;  // "0.5 x the node spacing ..."
};

// A steppable engine. step() guards, advances the engine and refuses non-finite outputs
// (SolverError); the adapters implement advance() and rebuild() and what they have of the mesh.
class SteppableSession {
 public:
  virtual ~SteppableSession() = default;
  SteppableSession(const SteppableSession&) = delete;
  SteppableSession& operator=(const SteppableSession&) = delete;

  // The returned reference stays valid until the next step or reset.
  const SessionOutput& step(const SessionCommand& c, double dt);
  // Back to the state before the first step (the engine is built again).
  void reset();
  const SessionOutput& output() const { return out_; }
  double time() const { return time_; }                    // s, sum of the steps' dt
  std::optional<double> depth() const { return previous_; }  // m, of the last step
  const std::string& engine() const { return engine_; }
  double defaultDt() const { return defaultDt_; }          // s, model.time_step
  const SessionGuard& guard() const { return guard_; }

  // The tissue mesh (realtime2d, realtime3d; none for lumped), in the centred tissue frame.
  virtual int dimension() const = 0;  // 2 or 3 coordinates per point
  virtual bool hasMesh() const { return false; }
  virtual std::size_t nodeCount() const { return 0; }
  virtual std::vector<double> nodePositions() const { return {}; }  // undeformed, dimension() per node
  virtual const Eigen::VectorXd& displacement() const;               // dimension() per node
  virtual std::vector<int> cells() const { return {}; }              // 4 node indices per quad / tet
  // The mesh's surface as triangles over all its nodes (3D: the block's boundary, outward;
  // 2D: every element, a collapsed quad once).
  virtual std::vector<int> surfaceTriangles() const { return {}; }
  // The nodes of each tissue.inclusions entry's material, in its order (indices of
  // nodePositions(); none without a mesh).
  virtual std::vector<std::vector<int>> inclusionNodes() const { return {}; }
  // The needle's centre line, base to tip, `points` >= 2 columns of dimension() rows.
  virtual void needleShape(int points, Eigen::MatrixXd& out) const;
  // The displacement copied for a reader in another thread, and the field from that copy.
  virtual void saveDisplacement(realtime::DisplacementState&) const {}
  virtual void displacementFrom(const realtime::DisplacementState&, Eigen::VectorXd& u) const { u.resize(0); }

 protected:
  SteppableSession(const Scenario& sc, const StepPlan& plan, SessionAxes axes);
  // One step of the engine to the guarded command; fills out (all but nothing it lacks).
  virtual void advance(const SessionCommand& c, double dt, std::optional<double> previous, SessionOutput& out) = 0;
  virtual void rebuild() = 0;

 private:
  void requireFiniteOutputs(const SessionCommand& c, double dt) const;

  std::string engine_;
  double defaultDt_ = 0.0;
  SessionGuard guard_;
  SessionOutput out_;
  double time_ = 0.0;
  std::optional<double> previous_;
};

// The session of the scenario's engine (its registration's EngineInfo::open);
// InputError naming model.engine for an engine that cannot be stepped.
std::unique_ptr<SteppableSession> openSession(const Scenario& sc);
// "lumped, realtime2d or realtime3d".
std::string steppableEngines();

}  // namespace needlesim::engines
