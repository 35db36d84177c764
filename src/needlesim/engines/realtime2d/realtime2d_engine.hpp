#pragma once
// The `realtime2d` engine: builds a real-time 2D FE Session (session.hpp) from a
// Scenario, runs its insertion profile and reports forces, tip deflection, needle
// shape, marker displacements and the tissue fields (seed 003 sections 3.1-3.5).
#include "needlesim/engines/engine.hpp"
#include "needlesim/engines/realtime2d/session.hpp"

namespace needlesim::engines {

// The Session configuration a scenario describes (throws InputError/SolverError
// with the limit broken when the scenario cannot run stably).
realtime2d::SessionConfig realtime2dConfig(const Scenario& scenario);

void runRealtime2d(const Scenario& scenario, ResultSink& sink, const RunOptions& options);
// How it steps (engines/step_guard.hpp): model.time_step against the mesh spacing along the depth.
StepPlan realtime2dStepPlan(const Scenario& scenario);

}  // namespace needlesim::engines
