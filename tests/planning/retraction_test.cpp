// The planner's retraction (docs/planning.md, "Targeting error"): the channel a retraction
// follows back, the closed loop pulling the tip back where the target is out of its reach, the
// plan turned into an insertion profile with its retract, and the entry out of the insertion
// plane that a scenario cannot state, explained in the reason of an infeasible plan.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include "needlesim/engines/memory_sink.hpp"
#include "needlesim/planning/channel.hpp"
#include "needlesim/planning/plan_run.hpp"
#include "needlesim/scenario/reader.hpp"

using namespace needlesim;
using namespace needlesim::planning;

namespace {

constexpr double pi = std::numbers::pi;

// The gel block of planner_test.cpp (curvature 1/240 mm, seed 002 gel C) with a target and
// a vessel; `plan` is the plan section's body.
Scenario gelWith(const std::string& plan) {
  return scenario::readText(fmt::format(R"(
name: retraction_test
tissue:
  block: {{length: 120 mm, width: 80 mm, height: 60 mm}}
  material: {{law: neo-hookean, C10: 7.55 kPa, nu: 0.45}}
  inclusions:
    - {{name: tumour, depth: 90 mm, lateral: 12 mm, elevation: 4 mm, radius: 3 mm, target: true,
       material: {{law: neo-hookean, C10: 15 kPa, nu: 0.45}}}}
    - {{name: vessel, shape: cylinder, depth: 45 mm, lateral: 6 mm, radius: 3 mm,
       material: {{law: neo-hookean, C10: 7.55 kPa, nu: 0.45}}}}
needle: {{outer_diameter: 0.54 mm, inner_diameter: 0 mm, length: 200 mm, bevel_angle: 34.85 deg, youngs_modulus: 50 GPa}}
insertion:
  profile:
    - insert: {{to: 100 mm, speed: 2.5 mm/s}}
model:
  engine: kinematic
  steering: {{curvature: 4.1667 1/m}}
plan:
{}
)", plan), "retraction_test.yaml");
}

// The gel example's plan (a reserve of 0.4 of the curvature) with the tip imaged every 25 mm
// only: the last segment, up to 31 mm, is inserted without a measurement, and the miss found
// at its end can no longer be corrected forward.
std::string sparsePlan(int max_retractions) {
  return fmt::format("  target: tumour\n  tolerance: 0.5 mm\n  avoid:\n    - {{inclusion: vessel, clearance: 2 mm}}\n"
                     "  entry_window: 10 mm\n  max_entry_angle: 10 deg\n  curvature_reserve: 0.4\n"
                     "  max_retractions: {}\n"
                     "  uncertainty: {{samples: 300, curvature_sd: 0.1, target_sd: 0.3 mm, entry_sd: 0.3 mm, "
                     "angle_sd: 0.5 deg, measurement_noise: 0.2 mm, measure_every: 25 mm}}\n",
                     max_retractions);
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : v[v.size() / 2];
}

}  // namespace

TEST(Retraction, AChannelPulledBackKeepsItsPathAndTheRotationsMadeSince) {
  // 30 mm at 1/100 mm, a half turn, 20 mm more; pulled back 35 mm the tip is at 15 mm of the
  // first arc, its bevel turned by the half turn made after it passed there.
  const double k = 10.0;
  Channel c(Pose{}, 1.0);
  c.follow(Arc{0.0, 0.03, k});
  c.follow(Arc{pi, 0.02, k});
  c.follow(Arc{0.0, 0.0, 0.0, 0.035});
  EXPECT_NEAR(c.depth(), 0.015, 1e-15);
  const double a = k * 0.015;  // turn of the arc at 15 mm, about model x: the path bends to -y
  EXPECT_NEAR(c.tip().p.x(), 0.0, 1e-12);
  EXPECT_NEAR(c.tip().p.y(), -(1 - std::cos(a)) / k, 1e-12);
  EXPECT_NEAR(c.tip().p.z(), std::sin(a) / k, 1e-12);
  const Vec3 axis(0.0, -std::sin(a), std::cos(a));
  EXPECT_NEAR((c.tip().R.col(2) - axis).norm(), 0.0, 1e-12);
  EXPECT_NEAR(c.tip().R.col(0).x(), -1.0, 1e-12);  // model x turned by pi about the axis
  // Re-inserted 15 mm with no rotation: the new branch curves the other way from the first arc.
  c.follow(Arc{0.0, 0.015, k});
  EXPECT_GT(c.tip().p.y(), -(1 - std::cos(2 * a)) / k + 1e-3);
}

TEST(Retraction, TheClosedLoopRetractsWhereTheTargetIsOutOfReachAndLowersTheP95) {
  const PlanOutcome without = planScenario(gelWith(sparsePlan(0)));
  const PlanOutcome with = planScenario(gelWith(sparsePlan(2)));
  ASSERT_TRUE(without.closed_loop && with.closed_loop);
  // The same plan and, per sample, the same draws and measurement noise: a sample that does
  // not retract ends where it did without; one that retracts had missed.
  std::vector<double> before, after;
  for (std::size_t i = 0; i < with.closed_loop->errors.size(); ++i) {
    EXPECT_EQ(without.closed_loop->retractions[i], 0);
    if (with.closed_loop->retractions[i] == 0) {
      EXPECT_EQ(with.closed_loop->errors[i], without.closed_loop->errors[i]);
      continue;
    }
    EXPECT_GT(with.closed_loop->retracted_to[i], 0.0);
    before.push_back(without.closed_loop->errors[i]);
    after.push_back(with.closed_loop->errors[i]);
  }
  EXPECT_GT(before.size(), 10u);
  EXPECT_EQ(without.closed_loop->mean_retractions, 0.0);
  EXPECT_TRUE(without.closed_loop->retracting_example.arcs.empty());
  // The retracting samples: missed beyond the tolerance (their median), re-inserted within it.
  EXPECT_GT(median(before), with.problem.tolerance);
  EXPECT_LT(median(after), with.problem.tolerance);
  EXPECT_LT(with.closed_loop->p95, without.closed_loop->p95);
}

TEST(Retraction, TheReportAndTheInsertionProfileCarryTheRetraction) {
  const Scenario sc = gelWith(sparsePlan(2));
  const PlanOutcome o = planScenario(sc);
  ASSERT_TRUE(o.closed_loop);
  const Plan& example = o.closed_loop->retracting_example;
  ASSERT_GT(example.retractions(), 0);
  MemorySink sink;
  reportPlan(sc, o, sink);
  EXPECT_GT(sink.results.at("closed_loop_retractions").value, 0.0);
  EXPECT_GT(sink.results.at("closed_loop_retracted_to").value, 0.0);
  const io::Table& t = sink.tables.at("closed_loop_retracting");
  int rows = 0;
  for (std::size_t r = 0; r < t.rows(); ++r)
    if (t.at(r, t.columnIndex("retract_before")) > 0) ++rows;
  EXPECT_EQ(rows, example.retractions());
  // The insertion profile: a retract to the depth of each retraction, at the insertion speed.
  const Scenario run = planAsScenario(sc, example, o.problem.kappa);
  int retracts = 0;
  for (const MotionSegment& m : run.insertion.segments)
    if (m.kind == MotionSegment::Kind::Retract) {
      ++retracts;
      EXPECT_NEAR(m.speed, 2.5e-3, 1e-15);
    }
  EXPECT_EQ(retracts, example.retractions());
  const MotionSegment& last = run.insertion.segments.back();
  EXPECT_NEAR(last.to_depth, example.length(), 1e-12);
}

TEST(Retraction, ATargetOnlyAnEntryOutOfTheInsertionPlaneReachesIsExplained) {
  // 20 mm above the insertion plane at 40 mm depth: an in-plane entry's tip leaves the plane by
  // at most 40^2 / (2 * 240) = 3.3 mm there; an entry at the target's elevation reaches it
  // straight ahead.
  const PlanOutcome o = planScenario(gelWith("  target_depth: 40 mm\n  target_elevation: 20 mm\n"
                                             "  max_entry_angle: 10 deg\n  max_rotations: 2\n  max_paths: 20000\n"));
  EXPECT_FALSE(o.search.feasible);
  EXPECT_NE(o.search.reason.find("out of the insertion plane"), std::string::npos) << o.search.reason;
  // In the plane it is planned, and a target out of reach from any entry gets no such note.
  EXPECT_TRUE(planScenario(gelWith("  target_depth: 40 mm\n  max_entry_angle: 10 deg\n")).search.feasible);
  const PlanOutcome far = planScenario(gelWith("  target_depth: 40 mm\n  target_lateral: 35 mm\n  target_elevation: 20 mm\n"));
  EXPECT_FALSE(far.search.feasible);
  EXPECT_EQ(far.search.reason.find("out of the insertion plane"), std::string::npos) << far.search.reason;
}
