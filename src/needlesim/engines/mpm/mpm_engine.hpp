#pragma once
// The MPM engine (seed 000) behind `model.engine: mpm`: builds the particle
// block and the rigid needle from the typed Scenario, drives the needle along
// the motion profile and reports forces, energies, markers and particle fields.
#include "needlesim/engines/engine.hpp"
#include "needlesim/engines/mpm/mpm_solver.hpp"

namespace needlesim::engines {

// The solver set-up of a scenario (block frame: x along the insertion axis from
// the entry face, y across the width, z across the height; origin at a corner).
struct MpmSetup {
  mpm::MpmConfig config;
  std::vector<mpm::MpmMaterial> materials;  // one per layer
  mpm::RigidBody needle;                    // placed at depth 0
  Eigen::Vector3d entry = Eigen::Vector3d::Zero();  // entry point on the entry face
  Eigen::Vector3d axis = Eigen::Vector3d::UnitX();  // insertion direction
  Eigen::Vector3d bevel0 = Eigen::Vector3d::UnitY();  // radial direction of the bevel at axial angle 0
};
MpmSetup mpmSetup(const Scenario& scenario);

// Runs the 3D MPM insertion (seed 000 sections 3-4; docs/models/mpm.md).
void runMpm(const Scenario& scenario, ResultSink& sink, const RunOptions& options);

}  // namespace needlesim::engines
