#pragma once
// Reports shared by the real-time engines' runs (realtime2d, realtime3d).
#include <vector>

#include "needlesim/engines/engine.hpp"
#include "needlesim/io/table.hpp"

namespace needlesim::engines {

// Values times 1000 (m -> mm for plots).
std::vector<double> realtimeMm(std::vector<double> v);
// Axial force and its parts (eqs 3.16, 3.23, 3.24) against tip depth and time, from a forces
// table with the columns force_total, force_stiffness, force_cutting, force_friction.
void plotAxialForces(const io::Table& forces, const Scenario& sc, ResultSink& sink);

// A real-time engine's run: the step guards, then the Run class (constructor with the scenario,
// sink and options; run(); finish()).
template <class Run>
void runRealtimeEngine(const Scenario& sc, ResultSink& sink, const RunOptions& options, const StepPlan& plan) {
  guardAndAnnounce(sc, plan, sink, options);
  Run run(sc, sink, options);
  run.run();
  run.finish();
}

}  // namespace needlesim::engines
