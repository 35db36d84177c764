#pragma once
// `needlesim plan --verify ENGINE`: the chosen plan run as a scenario (planAsScenario) through a
// physics engine that moves the bevel with the tissue deforming (realtime3d), and the executed
// miss distance set beside the planned one, split into what the steering model and what the
// tissue's deformation (the target's motion) contribute.
#include <string>

#include "needlesim/planning/plan_run.hpp"

namespace needlesim::planning {

struct Verification {
  std::string engine;
  double planned_miss = 0.0;   // m, kinematic plan
  double executed_miss = 0.0;  // m, engine's tip to the target where the tissue moved it
  double tip_gap = 0.0;        // m, engine's tip to the planned tip: the steering models' difference
  double target_motion = 0.0;  // m, displacement of the target: the tissue's deformation
  // The tip gap in two (an engine whose tip follows its channel, realtime3d path follow_tip):
  double tip_motion = 0.0;     // m, the tissue's displacement at the tip (deformation)
  double channel_gap = 0.0;    // m, the channel's end (the tip less that displacement) to the planned tip
  double seconds = 0.0;        // wall time of the engine's run
};

// InputError for an engine --verify does not take.
void checkVerifyEngine(const std::string& engine);
Verification verifyPlan(const Scenario& sc, const PlanOutcome& o, const std::string& engine);
// Reports the verification; returns its note.
std::string reportVerification(const Verification& v, ResultSink& sink);
// Plans, verifies a feasible plan in `engine` and writes the results folder.
PlanFolder planAndVerifyToFolder(const Scenario& sc, const std::string& engine, const std::filesystem::path& target,
                                 bool overwrite);

}  // namespace needlesim::planning
