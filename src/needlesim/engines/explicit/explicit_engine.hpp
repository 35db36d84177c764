#pragma once
// Engine "explicit": needle insertion into a tissue block with the explicit
// large-deformation FE solver (docs/models/explicit.md).
#include "needlesim/engines/engine.hpp"

namespace needlesim::engines {

void runExplicit(const Scenario& sc, ResultSink& sink, const RunOptions& options);

}  // namespace needlesim::engines
