#pragma once
// What the planner searches over, built from a scenario's plan section: the steering
// model's curvature (as the kinematic engine computes it), the target, the obstacles with
// their clearances, the entry family and the limits; and the plan it returns: an entry pose
// and a sequence of constant-curvature arcs separated by axial rotations of the bevel
// (the kinematic bevel-tip model of Webster et al. 2006, engines/steering/kinematic.hpp).
// Everything is in the tissue frame (needle/insertion_frame.hpp), metres and radians.
#include <string>
#include <vector>

#include "needlesim/engines/steering/kinematic.hpp"
#include "needlesim/insertion/insertion_spec.hpp"

namespace needlesim {
struct Scenario;
}

namespace needlesim::planning {

using steering::Mat3;
using steering::Pose;
using steering::Vec3;

// An inclusion to avoid: a sphere, or a cylinder whose axis runs along z through the tissue.
struct Obstacle {
  std::string name;
  bool cylinder = false;
  Vec3 centre = Vec3::Zero();
  double radius = 0.0;     // m
  double clearance = 0.0;  // m, kept between its surface and the needle axis
  // Distance from p to the surface (negative inside).
  double distance(const Vec3& p) const;
};

// One piece of a plan: pull the tip back `retract` along its channel (closed loop only), turn
// the bevel by `rotate` about the needle axis, then insert `length` with the tip curving at
// `curvature` (the needle's own, or less when duty-cycled).
struct Arc {
  double rotate = 0.0;     // rad
  double length = 0.0;     // m
  double curvature = 0.0;  // 1/m
  double retract = 0.0;    // m
};

struct Plan {
  double entry_offset = 0.0;  // m, insertion.entry_offset
  double entry_angle = 0.0;   // rad, insertion.entry_angle
  double roll = 0.0;          // rad, insertion.bevel_orientation
  std::vector<Arc> arcs;
  // The tip's final depth along its path (the arcs' lengths less the retractions).
  double length() const;
  int retractions() const;
  // Axial rotations during the insertion (the roll before entry is none).
  int rotations() const;
};

struct PlanProblem {
  double kappa = 0.0;       // 1/m, curvature with the bevel fixed
  double plan_kappa = 0.0;  // 1/m, the curvature the arcs are planned at (kappa less the reserve)
  bool duty_cycling = false;
  Vec3 target = Vec3::Zero();
  double tolerance = 1e-3;
  std::vector<Obstacle> obstacles;
  double needle_radius = 0.0;
  double offset_lo = 0.0, offset_hi = 0.0;  // m, entry offsets searched
  double angle_lo = 0.0, angle_hi = 0.0;    // rad, entry angles searched
  int max_rotations = 0;
  int max_retractions = 0;                  // closed loop: retractions allowed per insertion
  double entry_elevation = 0.0;             // m, entry point across the height (0: the insertion plane)
  double max_depth = 0.0;                   // m, longest tip path
  Vec3 lo = Vec3::Zero(), hi = Vec3::Zero();  // the tissue's box
  double sample_spacing = 5e-4;
  long max_paths = 100000;
  unsigned seed = 1;
  InsertionSpec insertion;  // the scenario's (start depth, bevel)
};

// The problem a scenario's plan section states. The curvature: model.steering.curvature, else
// the beam-on-foundation steady curvature of the tip loads (as engine kinematic). InputError
// for what cannot be planned (no plan section).
PlanProblem planProblem(const Scenario& sc);

// The tip pose at the entry point for an entry offset, angle and bevel roll (the kinematic
// engine's frame: model x = -outOfPlane, y = lateral, z = axial), at pb.entry_elevation.
Pose entryPose(const PlanProblem& pb, double offset, double angle, double roll);

// The pose after one arc, exactly (one SE(3) exponential), with its curvature scaled.
Pose arcEnd(const Pose& from, const Arc& arc, double curvature_scale = 1.0);

// The axial rotation that turns the bevel of `pose` towards the unit vector `b` (b normal to the axis).
double rollTowards(const Pose& pose, const Vec3& b);

// The rotation and insertion of one arc from `start` (its retraction left to the caller),
// appending the tip every `spacing` or closer (not the start); returns the end pose.
Pose traceArc(Pose start, const Arc& arc, double spacing, std::vector<Vec3>& out, double curvature_scale = 1.0);

// Samples the tip path of `arcs` from `start` every `spacing` or closer, appending to `out`
// (the start first; a retraction adds no points); returns the end pose.
Pose tracePath(const Pose& start, const std::vector<Arc>& arcs, double spacing, std::vector<Vec3>& out,
               double curvature_scale = 1.0);

}  // namespace needlesim::planning
