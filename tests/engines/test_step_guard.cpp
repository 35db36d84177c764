// The step guards of every engine (engines/step_guard.hpp): each engine's plan,
// the refusals with the field, value and what is allowed, the estimate and
// the budget, and the zero-force warning.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>
#include <string>

#include "needlesim/core/error.hpp"
#include "needlesim/engines/engine.hpp"
#include "needlesim/engines/memory_sink.hpp"
#include "needlesim/engines/mpm/mpm_engine.hpp"
#include "needlesim/engines/run_cost.hpp"
#include "needlesim/engines/step_guard.hpp"
#include "needlesim/scenario/reader.hpp"

namespace needlesim {
namespace {

std::string exampleText(const std::string& f) {
  std::stringstream in;
  in << std::ifstream(std::string(NEEDLESIM_SOURCE_DIR) + "/examples/" + f).rdbuf();
  return in.str();
}

// An example with `from` replaced by `to`.
Scenario edited(const std::string& file, const std::string& from, const std::string& to) {
  std::string text = exampleText(file);
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) text.replace(at, from.size(), to);
  return scenario::readText(text, file);
}

// The InputError preflight throws: its field and message.
InputError refusal(const Scenario& sc) {
  try {
    preflight(sc);
  } catch (const InputError& e) {
    return e;
  }
  ADD_FAILURE() << "accepted " << sc.source;
  return InputError({}, "", "", "", "");
}

void expectHas(const std::string& text, std::initializer_list<const char*> words) {
  for (const char* w : words) EXPECT_NE(text.find(w), std::string::npos) << "missing '" << w << "' in:\n" << text;
}

// A later segment too fast for the step (the whole profile is not): named by its own speed field.
TEST(StepGuard, ASegmentMovingTooFarPerStepIsNamedByItsSpeed) {
  const Scenario sc = edited("gelatin_18G_3mms.yaml", "- pause: {duration: 5 s}",
                             "- insert: {to: 75 mm, speed: 40 m/s}");
  const InputError e = refusal(sc);
  EXPECT_EQ(e.field(), "insertion.profile[1].insert.speed");
  expectHas(e.what(), {"'40 m/s'", "lumped", "moves the needle 40 mm per time step of 1 ms",
                       "half the thinnest layer (55 mm)", "at most 500 mm/s at this step",
                       "model.time_step at most 12.5 us"});
}

TEST(StepGuard, ASegmentWithTooFewStepsIsRefused) {
  const Scenario sc = edited("gelatin_18G_3mms.yaml", "- pause: {duration: 5 s}",
                             "- insert: {to: 75 mm, speed: 1 m/s}");  // 5 ms: 5 steps of 1 ms
  const InputError e = refusal(sc);
  EXPECT_EQ(e.field(), "insertion.profile[1].insert.speed");
  expectHas(e.what(), {"lasts 5 ms and gets 5 steps", "fewer than the 10", "at most 500 mm/s at this step",
                       "model.time_step at most 500 us"});
}

TEST(StepGuard, Realtime2dStepAgainstItsNodeSpacing) {
  // 80 mm over 20 intervals: 4 mm between path nodes; 3 m/s moves 3 mm a step of 1 ms (61 mm in 20 steps)
  const Scenario sc =
      edited("realtime2d/angled_base_rotation.yaml", "{to: 12 mm, speed: 3 mm/s}", "{to: 60 mm, speed: 3 m/s}");
  const InputError e = refusal(sc);
  EXPECT_EQ(e.field(), "insertion.profile[0].insert.speed");
  expectHas(e.what(), {"realtime2d", "node spacing along the depth", "(4 mm)", "at most 2 m/s at this step"});
}

TEST(StepGuard, ARotationNeedsItsStepsToo) {
  const Scenario sc = edited("realtime2d/angled_base_rotation.yaml", "rate: 2 deg/s", "rate: 1000 deg/s");
  const InputError e = refusal(sc);  // 5 deg at 1000 deg/s: 5 ms, 5 steps
  EXPECT_EQ(e.field(), "insertion.profile[1].rotate.rate");
  expectHas(e.what(), {"'1e+03 deg/s'", "gets 5 steps", "a lower rate", "model.time_step at most 500 us"});
}

// The explicit engine stops (exit 3) when the needle penetrates half an element; its set-up refuses first.
TEST(StepGuard, ExplicitRefusesASpeedItsStableStepCannotFollow) {
  const Scenario sc = edited("explicit/deformable_needle_2d.yaml", "speed: 10 mm/s", "speed: 50 m/s");
  const InputError e = refusal(sc);
  expectHas(e.what(), {"explicit", "the smallest element", "model.explicit.mass_scaling"});
  EXPECT_THROW(runInMemory(sc), InputError);
}

TEST(StepGuard, SteeringEnginesCountTheirIncrementsAgainstTheBudget) {
  const Scenario ok = scenario::readText(exampleText("steering/table2_gelC_054_kinematic.yaml"), "kinematic.yaml");
  EXPECT_EQ(preflight(ok).steps, 150.0);  // 150 mm in 1 mm increments; the speed does not enter
  std::string text = exampleText("steering/table2_gelC_054_kinematic.yaml") + "output: {max_steps: 100}\n";
  const InputError e = refusal(scenario::readText(text, "kinematic.yaml"));
  EXPECT_EQ(e.field(), "output.max_steps");
  expectHas(e.what(), {"'100'", "150 steps", "output.max_steps of at least 150", "model.steering.increment"});
}

TEST(StepGuard, EveryEngineHasAPreflight) {
  for (const EngineInfo& e : engineRegistry()) EXPECT_TRUE(static_cast<bool>(e.preflight)) << e.name;
}

TEST(StepGuard, EstimateText) {
  EXPECT_EQ((StepEstimate{391, true, 2304, "points", 0.34}).text(), "at least 391 steps x 2304 points, about 0.34 s");
  EXPECT_EQ((StepEstimate{1.2e6, false, 0, "", 2400}).text(), "1.2e+06 steps, about 40 min");
  EXPECT_EQ((StepEstimate{1e6, false, 0, "", 150}).text(), "1e+06 steps, about 2.5 min");
  EXPECT_EQ((StepEstimate{1, false, 0, "", NAN}).text(), "1 step");
}

// The time: the run's fixed cost, the set-up, then the steps (grown where adaptive) at their
// per-step and per-update costs, shared by the threads (run_cost.hpp).
TEST(StepGuard, EstimateSecondsFromThePlansCosts) {
  const Scenario sc = scenario::defaultScenario();  // lumped, 1 ms steps
  StepPlan p = fixedStepPlan(sc, "test");
  p.spacing = 1.0;
  const double steps = guardSteps(sc, p).steps;
  EXPECT_TRUE(std::isnan(guardSteps(sc, p).seconds));  // no cost known: steps only
  p.setupSeconds = 2.0;
  p.secondsPerStep = 1e-4;
  p.updatesPerStep = 100;
  p.secondsPerUpdate = 1e-6;
  p.stepGrowth = 1.5;
  p.threads = 3;
  EXPECT_DOUBLE_EQ(guardSteps(sc, p).seconds,
                   run_cost::kRunSeconds + 2.0 + steps * 1.5 * (1e-4 + 100 * 1e-6) / (1.0 + 2 * run_cost::kParallelEfficiency));
  p.serialSecondsPerStep = 3e-5;  // one thread's part, whatever the threads
  EXPECT_DOUBLE_EQ(guardSteps(sc, p).seconds,
                   run_cost::kRunSeconds + 2.0 +
                       steps * 1.5 * ((1e-4 + 100 * 1e-6) / (1.0 + 2 * run_cost::kParallelEfficiency) + 3e-5));
}

// Every engine's plan gives a time; mpm counts the points its filling rule keeps (the imported
// gland: the lattice points inside the mesh, not the block's), and its steps grow on a
// strain-stiffening tissue.
TEST(StepGuard, EveryExampleEngineEstimatesItsTime) {
  for (const char* f : {"gelatin_18G_3mms.yaml", "realtime2d/thesis_gelatin_18G_3mms.yaml", "realtime3d/quick_block.yaml",
                        "steering/flip_s_curve.yaml", "explicit/deformable_needle_2d.yaml", "mpm/quick_needle_block.yaml"})
    EXPECT_TRUE(std::isfinite(preflight(scenario::readText(exampleText(f), f)).seconds)) << f;
  const StepEstimate gland = preflight(scenario::readFile(std::string(NEEDLESIM_SOURCE_DIR) +
                                                          "/examples/anatomy/prostate_tumour_mpm.yaml"));
  EXPECT_EQ(gland.updatesPerStep, 44223.0);  // as the run reports (results: particles)
}

// mpm's steps grow by its needle contact (run_cost.hpp): with CFEMP the lips the bevel parts hardly
// stiffen in a wide block (organ_block_1m took 1341 steps for its first step's 1086), more where the
// shaft's drag compresses a narrow one, and most with grid contact, which acts a cell into the
// tissue. The contact's own work per step: the cut's strip tests shared by the threads, CFEMP's
// pair search on one.
TEST(StepGuard, MpmCostsItsNeedleContact) {
  const std::string f = "mpm/organ_block_1m.yaml";
  const auto plan = [&](const std::string& from, const std::string& to) {
    return engines::mpmStepPlan(edited(f, from, to));
  };
  const std::string contact = "field_interval: 0 s";
  const StepPlan cfemp = plan(contact, contact);
  const StepPlan grid = plan(contact, contact + "\n    contact: grid");
  const StepPlan narrow = plan("width: 50 mm, height: 50 mm", "width: 10 mm, height: 10 mm");
  const StepPlan whole = plan(contact, contact + "\n    parting: none");
  EXPECT_LT(cfemp.stepGrowth, 1.5 * 1341.0 / 1086.0);
  EXPECT_GT(cfemp.stepGrowth, 1341.0 / 1086.0 / 1.5);
  EXPECT_GT(narrow.stepGrowth, 1.1 * cfemp.stepGrowth);
  EXPECT_GT(grid.stepGrowth, 1.5 * cfemp.stepGrowth);
  EXPECT_GT(cfemp.serialSecondsPerStep, 0.0);  // CFEMP's pair search
  EXPECT_EQ(grid.serialSecondsPerStep, 0.0);
  EXPECT_GT(cfemp.secondsPerStep, 0.0);  // the cut's strip
  EXPECT_EQ(whole.secondsPerStep, 0.0);
}

// The bonded tip (model.explicit.tip: bonded, one static solve) is costed as every 2D explicit run,
// by its elements (the 24 x 24 mm block in 0.2 mm quads, less the squares inside the tip), and its
// run announces the estimate as the others do.
TEST(StepGuard, TheBondedTipEstimatesItsTimeAndAnnouncesIt) {
  const std::string f = "cohesive/seed004_fig13a_bonded_tip.yaml";
  const Scenario sc = scenario::readText(exampleText(f), f);
  const StepEstimate e = preflight(sc);
  EXPECT_EQ(e.steps, 1.0);
  EXPECT_GT(e.updatesPerStep, 14000.0);
  EXPECT_LE(e.updatesPerStep, 120.0 * 120.0);
  ASSERT_TRUE(std::isfinite(e.seconds));
  EXPECT_DOUBLE_EQ(e.seconds, run_cost::kRunSeconds + e.updatesPerStep * (run_cost::kExplicitSetupPerElement +
                                                                          run_cost::kExplicitPlaneElement));
  const MemorySink run = runInMemory(sc);
  const auto announced = std::count_if(run.notes.begin(), run.notes.end(), [&](const std::string& n) {
    return n.find("Estimated before the run: " + e.text()) != std::string::npos;
  });
  EXPECT_EQ(announced, 1) << e.text();
}

TEST(StepGuard, ZeroForceWithTheTipInsideIsAWarning) {
  const Scenario sc = scenario::defaultScenario();  // 70 mm deep
  MemorySink zero, some;
  warnZeroForce(sc, 0.0, zero);
  ASSERT_EQ(zero.warnings.size(), 1u);
  expectHas(zero.warnings.front(), {"stayed 0 N", "70 mm"});
  warnZeroForce(sc, 0.5, some);
  EXPECT_TRUE(some.warnings.empty());
}

}  // namespace
}  // namespace needlesim
