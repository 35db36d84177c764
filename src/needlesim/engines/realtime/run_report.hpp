#pragma once
// Reports shared by the real-time engines' runs (realtime2d, realtime3d).
#include <chrono>
#include <cstddef>
#include <vector>

#include "needlesim/engines/engine.hpp"
#include "needlesim/io/table.hpp"

namespace needlesim::engines {

// Values times 1000 (m -> mm for plots).
std::vector<double> realtimeMm(std::vector<double> v);
// Axial force and its parts (eqs 3.16, 3.23, 3.24) against tip depth and time, from a forces
// table with the columns force_total, force_stiffness, force_cutting, force_friction.
void plotAxialForces(const io::Table& forces, const Scenario& sc, ResultSink& sink);

// When a real-time run steps, samples the forces table and writes fields: `steps` steps of dt up to
// the motion's duration (the last one shortened), a row every `every` steps and fields every
// `fieldEvery` (0: none), both also at the last step.
struct RunCadence {
  RunCadence(double duration, double dt, double outputInterval, double fieldInterval);
  double timeOf(long long k) const { return k * dt < duration ? k * dt : duration; }
  bool sample(long long k) const { return k % every == 0 || k == steps; }
  bool field(long long k) const { return fieldEvery > 0 && (k % fieldEvery == 0 || k == steps); }
  std::size_t rows() const { return static_cast<std::size_t>(steps / every + 2); }
  double duration = 0.0, dt = 0.0;
  long long steps = 0, every = 1, fieldEvery = 0;
};

// Builds a value with make() and adds the wall-clock time it took to `seconds` (a session's set-up).
template <class Make>
auto timed(double& seconds, Make make) {
  const auto wall0 = std::chrono::steady_clock::now();
  auto value = make();
  seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  return value;
}

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
