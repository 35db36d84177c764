#pragma once
#include "needlesim/engines/engine.hpp"

namespace needlesim::engines {
// Runs the lumped insertion-force model (seed 003 section 3.2) over the
// scenario's motion profile; reports forces.csv and the key results.
void runLumped(const Scenario& scenario, ResultSink& sink, const RunOptions& options);
// How it steps (engines/step_guard.hpp): model.time_step against the thinnest layer.
StepPlan lumpedStepPlan(const Scenario& scenario);
}  // namespace needlesim::engines
