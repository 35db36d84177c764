#pragma once
// The `realtime3d` engine: builds a real-time 3D FE Session (session.hpp) from a Scenario,
// runs its insertion profile and reports the 3D needle force, tip position and deflection
// in both bending planes, the needle shape and the tissue fields (docs/models/realtime3d.md).
#include "needlesim/engines/engine.hpp"
#include "needlesim/engines/realtime3d/session.hpp"

namespace needlesim::engines {

// The Session configuration a scenario describes (InputError / SolverError on what it cannot run).
realtime3d::SessionConfig realtime3dConfig(const Scenario& scenario);
void runRealtime3d(const Scenario& scenario, ResultSink& sink, const RunOptions& options);
// How it steps (engines/step_guard.hpp): model.time_step against the node spacing along the depth.
StepPlan realtime3dStepPlan(const Scenario& scenario);

}  // namespace needlesim::engines
