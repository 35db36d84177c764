#pragma once
// Engine "explicit": needle insertion into a tissue block with the explicit
// large-deformation FE solver (docs/models/explicit.md).
#include "needlesim/engines/engine.hpp"

namespace needlesim::engines {

void runExplicit(const Scenario& sc, ResultSink& sink, const RunOptions& options);
// How it steps (engines/step_guard.hpp), from the set-up a run would build
// (the mesh's stable step against its smallest element).
StepPlan explicitStepPlan(const Scenario& sc);

}  // namespace needlesim::engines
