#pragma once
// The MPM engine (seed 000) behind `model.engine: mpm`: builds the particle
// block and the rigid needle from the typed Scenario, drives the needle along
// the motion profile and reports forces, energies, markers and particle fields.
#include <cstddef>
#include <vector>

#include "needlesim/engines/engine.hpp"
#include "needlesim/engines/mpm/mpm_solver.hpp"
#include "needlesim/needle/insertion_frame.hpp"

namespace needlesim::engines {

// The solver set-up of a scenario. The solver's frame is the tissue frame
// (needle/insertion_frame.hpp) moved by `shift` = needle::cornerShift, so that
// its origin is the block's corner (x along the depth, y across the width, z
// across the height).
struct MpmSetup {
  mpm::MpmConfig config;
  // One per layer, then one per inclusion (material index = layer, or layers + inclusion).
  std::vector<mpm::MpmMaterial> materials;
  mpm::RigidBody needle;  // placed at depth 0
  needle::InsertionFrame frame;
  Eigen::Vector3d shift = Eigen::Vector3d::Zero();  // tissue frame -> solver frame
  Eigen::Vector3d entry = Eigen::Vector3d::Zero();  // entry point, solver frame
  double cutDepth = 0.0;  // model.mpm.parting "path": the depth the pre-cut reaches (0: the cut follows the tip)
};
// Throws InputError naming the field for what mpm cannot honour.
MpmSetup mpmSetup(const Scenario& scenario);

// Places the needle with its axis point level with the tip at `depth` along
// the axis, turned about it so that its bevel looks to `bevelSide`, moving
// at `speed` along the axis.
void placeNeedle(mpm::RigidBody& needle, const MpmSetup& setup, double depth, const Eigen::Vector3d& bevelSide,
                 double speed);
// The needle's foremost point (the sharp point of a bevel) in the tissue frame
// when placed as placeNeedle does.
Eigen::Vector3d needleTip(const MpmSetup& setup, double depth, const Eigen::Vector3d& bevelSide);

// Adds the block's material points layer by layer; the points inside an
// inclusion take its material (body 1 when it slides). Returns the points of
// each inclusion, in the order of tissue.inclusions.
std::vector<std::vector<std::size_t>> addTissue(mpm::MpmSolver& solver, const Scenario& scenario,
                                                const MpmSetup& setup);

// How it steps (engines/step_guard.hpp): the first step of eqs 25-26 (the
// tissue at rest) against the grid spacing; the wall time from the points.
// Refuses, as mpmSetup, what mpm cannot honour.
StepPlan mpmStepPlan(const Scenario& scenario);

// Runs the 3D MPM insertion (seed 000 sections 3-4; docs/models/mpm.md).
void runMpm(const Scenario& scenario, ResultSink& sink, const RunOptions& options);

}  // namespace needlesim::engines
