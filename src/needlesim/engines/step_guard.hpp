#pragma once
// Before the first step of any engine: does its step resolve the insertion
// profile, how many steps (and, where measured, how much wall time) will the
// run take, and is that within output.max_steps? One set of rules for every
// engine; each engine only says how it steps (StepPlan). `needlesim check`
// applies the same rules through EngineInfo::preflight.
// docs/scenario-format.md "Step guards and the run budget".
#include <cmath>
#include <functional>
#include <string>

#include "needlesim/scenario/scenario.hpp"

namespace needlesim {

class ResultSink;
struct RunOptions;

// How an engine steps through the insertion profile.
struct StepPlan {
  std::string engine;
  // Time-stepping engines: the (first) time step, how it comes about, the
  // field that sets it with its value, and that field's setting for a step of
  // at most a given length. dt = 0: the engine steps in depth (`steps` below).
  double dt = 0.0;               // s
  std::string dtSetBy;           // "model.time_step"
  std::string dtField;           // "model.time_step"
  std::string dtValue;           // "1 ms"
  std::function<std::string(double maxStep)> stepAllowed;  // "model.time_step at most 0.1 ms"
  // The step can only shrink during the run (adaptive stable steps): the
  // estimate is then a lower bound.
  bool adaptive = false;
  // What lowers the step count, for a run above output.max_steps.
  std::string fewerSteps;        // "a larger model.time_step"
  // The length the needle may cross only over several steps (grid or element
  // spacing, the thinnest layer) and what it is, for the messages.
  double spacing = 0.0;          // m
  std::string spacingName;       // "the grid spacing (model.mpm.grid_spacing)"
  // Depth-stepping engines: their step count.
  double steps = 0.0;
  // Cost for a time estimate (the constants: engines/run_cost.hpp): updates (points,
  // elements, nodes) per step; CPU seconds of one update and of the rest of a step on one
  // thread (shared by the threads, or serial); the set-up before the first step; the threads
  // that share the steps.
  double updatesPerStep = 0.0;
  std::string updates;           // "points", "elements"
  double secondsPerUpdate = 0.0;
  double secondsPerStep = 0.0;
  double serialSecondsPerStep = 0.0;  // the part of a step one thread does whatever the threads
  double setupSeconds = 0.0;
  int threads = 1;
  // Adaptive steps: the steps the time assumes per step of the first step's count (the step
  // shrinks as the tissue stiffens; run_cost.hpp).
  double stepGrowth = 1.0;
};

// The cost of a run estimated before its first step.
struct StepEstimate {
  double steps = 0.0;
  bool atLeast = false;  // a lower bound (StepPlan::adaptive)
  double updatesPerStep = 0.0;
  std::string updates;
  double seconds = NAN;  // wall time on an otherwise idle machine; NaN where no cost is known
  // "at least 391 steps x 2304 points, about 0.9 s"
  std::string text() const;
};

// The largest part of StepPlan::spacing the needle may travel in one step: as
// the explicit engine's needle contact, which stops when the needle penetrates
// the tissue by more than half its smallest element (explicit/solver.cpp).
inline constexpr double kMaxTravelPerStep = 0.5;
// The fewest steps a moving segment of the profile (insert, retract, rotate)
// may get: with fewer, an engine that samples the profile at its steps cuts
// the segment's start or end by more than a tenth.
inline constexpr double kMinStepsPerSegment = 10.0;

// The estimate of the plan, after refusing with an InputError (the field, its
// value, the step and what is allowed):
// - a time step longer than the whole motion where a shorter one is needed
//   (naming StepPlan::dtField);
// - a segment that moves the needle more than kMaxTravelPerStep x spacing in
//   a step or gets fewer than kMinStepsPerSegment steps (naming the segment's
//   speed or rotation rate);
// - an estimate above output.max_steps (naming it).
StepEstimate guardSteps(const Scenario& sc, const StepPlan& plan);

// The plan of an engine stepping by model.time_step (the spacing left to the engine).
StepPlan fixedStepPlan(const Scenario& sc, const std::string& engine);

// StepPlan::stepAllowed for a stable step set by mass scaling (the step grows
// with its square root): "<field> at most S" for a step of at most maxStep,
// or, where even 1 is too much, that and `shorter` (what else shortens it).
std::function<std::string(double)> massScaledStep(const std::string& field, double scaling, double dt,
                                                  const std::string& shorter);

// guardSteps, then the estimate on the terminal (when options.progress) and
// among the run's notes. Engines call this in their set-up.
StepEstimate guardAndAnnounce(const Scenario& sc, const StepPlan& plan, ResultSink& sink, const RunOptions& options);

// A warning when the force on the needle never left zero although the
// tip went into the tissue: the steps did not resolve the contact.
void warnZeroForce(const Scenario& sc, double peakForce, ResultSink& sink);

}  // namespace needlesim
