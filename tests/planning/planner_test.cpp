// The path planner (docs/planning.md): zero rotations for a target the needle's own arc reaches,
// a target beyond the curvature's reach refused as infeasible, the clearance kept on every path
// returned, the predicted error distribution against a direct Monte Carlo of engine kinematic,
// the plan section's refusals, and `needlesim plan` on the gel example.
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>

#include "needlesim/core/error.hpp"
#include "needlesim/engines/memory_sink.hpp"
#include "needlesim/planning/plan_run.hpp"
#include "needlesim/planning/verify.hpp"
#include "needlesim/scenario/reader.hpp"

using namespace needlesim;
using namespace needlesim::planning;

namespace {

// A 120 x 80 x 60 mm gel block, a 0.54 mm bevel needle of curvature 1/240 mm (seed 002 Table 2,
// gel C), a 3 mm vessel (cylinder) and a target; `plan` is the plan section's body.
std::string scenarioText(const std::string& plan, const std::string& needle_extra = "",
                         const std::string& steering = "curvature: 4.1667 1/m") {
  return fmt::format(R"(
name: plan_test
tissue:
  block: {{length: 120 mm, width: 80 mm, height: 60 mm}}
  material: {{law: neo-hookean, C10: 7.55 kPa, nu: 0.45}}
  interaction: {{K_T: 12.61 kN/m^2}}
  inclusions:
    - {{name: tumour, depth: 90 mm, lateral: 12 mm, elevation: 4 mm, radius: 3 mm, target: true,
       material: {{law: neo-hookean, C10: 15 kPa, nu: 0.45}}}}
    - {{name: vessel, shape: cylinder, depth: 45 mm, lateral: 6 mm, radius: 3 mm,
       material: {{law: neo-hookean, C10: 7.55 kPa, nu: 0.45}}}}
    - {{name: cyst, depth: 60 mm, lateral: -10 mm, radius: 4 mm,
       material: {{law: neo-hookean, C10: 7.55 kPa, nu: 0.45}}}}
needle: {{outer_diameter: 0.54 mm, inner_diameter: 0 mm, length: 200 mm, bevel_angle: 34.85 deg, youngs_modulus: 50 GPa{}}}
insertion:
  profile:
    - insert: {{to: 100 mm, speed: 2.5 mm/s}}
model:
  engine: kinematic
  steering: {{{}}}
plan:
{}
)", needle_extra, steering, plan);
}

Scenario scenarioWith(const std::string& plan, const std::string& needle_extra = "",
                      const std::string& steering = "curvature: 4.1667 1/m") {
  return scenario::readText(scenarioText(plan, needle_extra, steering), "plan_test.yaml");
}

// The smallest distance of a plan's path, traced every 10 um, to an obstacle's surface.
double tracedDistance(const PlanProblem& pb, const Plan& plan, const Obstacle& o) {
  std::vector<Vec3> pts;
  tracePath(entryPose(pb, plan.entry_offset, plan.entry_angle, plan.roll), plan.arcs, 1e-5, pts);
  double d = 1e9;
  for (const Vec3& p : pts) d = std::min(d, o.distance(p));
  return d;
}

// Two-sample Kolmogorov-Smirnov statistic.
double ksStatistic(std::vector<double> a, std::vector<double> b) {
  std::sort(a.begin(), a.end());
  std::sort(b.begin(), b.end());
  double d = 0.0;
  std::size_t i = 0, j = 0;
  while (i < a.size() && j < b.size()) {
    const double x = std::min(a[i], b[j]);
    while (i < a.size() && a[i] <= x) ++i;
    while (j < b.size() && b[j] <= x) ++j;
    d = std::max(d, std::abs(double(i) / a.size() - double(j) / b.size()));
  }
  return d;
}

}  // namespace

TEST(Planner, AStraightAheadTargetIsPlannedWithZeroRotations) {
  // The bevel needle: its own arc reaches a target straight ahead once the entry is tilted.
  const Scenario bevel = scenarioWith(
      "  target_depth: 80 mm\n  tolerance: 0.2 mm\n  max_entry_angle: 10 deg\n  max_rotations: 3\n");
  const PlanOutcome o = planScenario(bevel);
  ASSERT_TRUE(o.search.feasible) << o.search.reason;
  EXPECT_EQ(o.search.best.plan.rotations(), 0);
  EXPECT_EQ(o.search.best.plan.arcs.size(), 1u);
  EXPECT_LE(o.search.best.miss, 0.2e-3);
  // A conical tip goes straight: the entry aimed at the target, no rotation.
  const Scenario conical = scenarioWith("  target_depth: 80 mm\n  target_lateral: 5 mm\n  tolerance: 0.2 mm\n"
                                        "  max_entry_angle: 10 deg\n  max_rotations: 3\n",
                                        ", tip: conical", "increment: 1 mm");
  const PlanOutcome c = planScenario(conical);
  ASSERT_TRUE(c.search.feasible) << c.search.reason;
  EXPECT_EQ(c.problem.kappa, 0.0);
  EXPECT_EQ(c.search.best.plan.rotations(), 0);
  EXPECT_LE(c.search.best.miss, 0.2e-3);
}

TEST(Planner, AnOffAxisTargetBeyondTheCurvatureIsRefusedAsInfeasible) {
  // Entering normal to the face at one point, a 240 mm radius deflects the tip by at most
  // 40^2 / (2 * 240) = 3.3 mm at 40 mm depth: a target 25 mm off the axis is out of reach.
  const Scenario sc = scenarioWith("  target_depth: 40 mm\n  target_lateral: 25 mm\n  max_rotations: 2\n");
  const PlanOutcome o = planScenario(sc);
  EXPECT_FALSE(o.search.feasible);
  EXPECT_NE(o.search.reason.find("beyond the reach of the needle's curvature"), std::string::npos) << o.search.reason;
  EXPECT_GT(o.search.best.miss, 20e-3);  // the closest approach: at least 25 - 3.3 mm off, less the depth slack
  EXPECT_FALSE(o.search.best.points.empty());
}

TEST(Planner, EveryReturnedPathKeepsItsClearance) {
  // Targets behind the vessel and beside the cyst; each feasible plan returned, traced 50 times
  // finer than the search checked it, keeps every clearance.
  int checked = 0;
  for (const char* where : {"target: tumour", "target_depth: 80 mm\n  target_lateral: 6 mm",
                            "target_depth: 75 mm\n  target_lateral: -10 mm\n  target_elevation: 2 mm"}) {
    const Scenario sc = scenarioWith(fmt::format("  {}\n  avoid:\n    - {{inclusion: vessel, clearance: 2 mm}}\n"
                                                 "    - {{inclusion: cyst, clearance: 1.5 mm}}\n  entry_window: 15 mm\n"
                                                 "  max_entry_angle: 15 deg\n  max_rotations: 2\n", where));
    const PlanOutcome o = planScenario(sc);
    ASSERT_TRUE(o.search.feasible) << where << ": " << o.search.reason;
    for (const CheckedPath& p : o.search.found) {
      for (const Obstacle& ob : o.problem.obstacles)
        EXPECT_GE(tracedDistance(o.problem, p.plan, ob), ob.clearance) << where << " " << ob.name;
      ++checked;
    }
  }
  EXPECT_GT(checked, 3);
}

TEST(Planner, ThePredictedErrorDistributionIsADirectMonteCarloOfEngineKinematic) {
  const Scenario sc = scenarioWith("  target: tumour\n  max_entry_angle: 10 deg\n  uncertainty: {samples: 4000, "
                                   "curvature_sd: 0.1, seed: 3}\n");
  const PlanOutcome o = planScenario(sc);
  ASSERT_TRUE(o.search.feasible && o.open_loop);
  // Engine kinematic runs the plan as a scenario with a curvature drawn from the same spread.
  Scenario planned = planAsScenario(sc, o.search.best.plan, o.problem.kappa);
  planned.tissue.inclusions.clear();  // engine kinematic models none (the target is a point here)
  std::mt19937_64 rng(11);
  std::normal_distribution<double> n(0.0, 1.0);
  std::vector<double> direct;
  for (int i = 0; i < 300; ++i) {
    Scenario run = planned;
    run.model.steering.curvature = o.problem.kappa * std::max(0.0, 1.0 + 0.1 * n(rng));
    const MemorySink m = runInMemory(run);
    const io::Table& tip = m.tables.at("tip_path");
    const std::size_t last = tip.rows() - 1;
    const Vec3 end(tip.at(last, tip.columnIndex("tip_x")), tip.at(last, tip.columnIndex("tip_y")),
                   tip.at(last, tip.columnIndex("tip_z")));
    direct.push_back((end - o.problem.target).norm());
  }
  // Same distribution: the two-sample Kolmogorov-Smirnov statistic under its 1 % critical value
  // 1.63 sqrt((n + m) / (n m)).
  const double n1 = static_cast<double>(o.open_loop->errors.size()), n2 = static_cast<double>(direct.size());
  EXPECT_LT(ksStatistic(o.open_loop->errors, direct), 1.63 * std::sqrt((n1 + n2) / (n1 * n2)));
  EXPECT_GT(o.open_loop->p95, o.open_loop->p50);
}

TEST(Planner, ContradictoryOrUnreachablePlanSectionsAreInputErrors) {
  const std::pair<const char*, const char*> cases[] = {
      {"  target: vessel\n", "is not marked target: true"},
      {"  target: tumor\n", "did you mean 'tumour'"},
      {"  target_depth: 130 mm\n", "outside the"},
      {"  target: tumour\n  avoid:\n    - {inclusion: tumour}\n", "is the target"},
      {"  target: tumour\n  max_depth: 60 mm\n", "shorter than the target's depth"},
      {"  target: tumour\n  max_depth: 300 mm\n", "longer than the needle"},
      {"  tolerance: 1 mm\n", "the plan has no target"},
      {"  target: tumour\n  choose: risk\n", "needs a predicted risk"},
  };
  for (const auto& [plan, message] : cases) {
    try {
      scenarioWith(plan);
      ADD_FAILURE() << "accepted: " << plan;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(message), std::string::npos) << e.what();
    }
  }
}

TEST(PlanExamples, GelBlockPlansAroundTheVesselAndWritesItsFolder) {
  const std::filesystem::path out = std::filesystem::temp_directory_path() / fmt::format("plan_gel_{}", ::getpid());
  std::filesystem::remove_all(out);
  const std::string cmd = fmt::format("{} plan {}/examples/planning/gel_block.yaml -q -o {}", NEEDLESIM_BINARY,
                                      NEEDLESIM_SOURCE_DIR, out.string());
  ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
  for (const char* f : {"summary.json", "plan.csv", "path.csv", "error_distribution.csv", "report.html",
                        "planned_path.xdmf", "planned_path.h5"})
    EXPECT_TRUE(std::filesystem::exists(out / f)) << f;
  std::ifstream in(out / "summary.json");
  const auto summary = nlohmann::json::parse(in);
  const auto value = [&](const std::string& key) { return summary["results"][key]["value"].get<double>(); };
  EXPECT_EQ(value("feasible"), 1.0);
  EXPECT_GE(value("clearance_vessel"), 2e-3);
  EXPECT_LT(value("closed_loop_error_p95"), 1e-3);  // with 0.2 mm measurement noise
  std::filesystem::remove_all(out);
}

TEST(PlanExamples, AnUnreachableTargetExitsWithFourAndSaysWhy) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / fmt::format("plan_far_{}", ::getpid());
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "far.yaml") << scenarioText("  target_depth: 40 mm\n  target_lateral: 25 mm\n");
  const std::string cmd = fmt::format("{} plan {} -q -o {} 2>/dev/null", NEEDLESIM_BINARY, (dir / "far.yaml").string(),
                                      (dir / "out").string());
  const int status = std::system(cmd.c_str());
  EXPECT_EQ(WEXITSTATUS(status), 4);
  std::ifstream in(dir / "out" / "summary.json");
  const auto summary = nlohmann::json::parse(in);
  EXPECT_EQ(summary["results"]["feasible"]["value"].get<double>(), 0.0);
  EXPECT_NE(summary["warnings"].dump().find("beyond the reach"), std::string::npos);
  std::filesystem::remove_all(dir);
}

TEST(PlanExamples, VerifyInRealtime3dSetsTheExecutedMissBesideThePlannedOne) {
  // 20 mm with a 500 mm radius: the plan's arc leaves its entry axis by at most 20^2 / (2 * 500)
  // = 0.4 mm. realtime3d's needle follows the channel its tip cuts on the plan's arc, so its tip
  // ends within the tissue's motion there of the planned tip, far less than that deviation; the
  // nodule's motion adds to the miss.
  const Scenario sc = scenario::readFile(std::string(NEEDLESIM_SOURCE_DIR) + "/examples/planning/gelatin_verify.yaml");
  const PlanOutcome o = planScenario(sc);
  ASSERT_TRUE(o.search.feasible) << o.search.reason;
  const Verification v = verifyPlan(sc, o, "realtime3d");
  EXPECT_LE(v.tip_gap, 0.4e-3);
  EXPECT_GT(v.target_motion, 0.0);
  EXPECT_LE(v.executed_miss, v.planned_miss + v.tip_gap + v.target_motion + 1e-12);
  EXPECT_THROW(checkVerifyEngine("lumped"), InputError);
}

// The gel example steers 11 mm off its entry axis. A relative curvature error e moves the tip by
// e times that steering displacement (to first order), so the plan's own curvature spread
// (plan.uncertainty.curvature_sd, 10 %) is the tolerance the engine's tip is held to; the
// executed miss is then within that plus the target's motion of the planned one.
TEST(PlanExamples, VerifyTheSteeredGelPlanInRealtime3d) {
  const Scenario sc = scenario::readFile(std::string(NEEDLESIM_SOURCE_DIR) + "/examples/planning/gel_block.yaml");
  const PlanOutcome o = planScenario(sc);
  ASSERT_TRUE(o.search.feasible) << o.search.reason;
  const std::vector<Vec3>& p = o.search.best.points;
  const Vec3 axis = (p[1] - p[0]).normalized(), end = p.back() - p[0];
  const double steered = (end - end.dot(axis) * axis).norm();
  const double tol = sc.plan.uncertainty.curvature_sd * steered;
  const Verification v = verifyPlan(sc, o, "realtime3d");
  std::printf("steered %.2f mm: executed miss %.3f mm, planned %.3f mm, tip gap %.3f mm (tissue %.3f, channel %.3f), "
              "target motion %.3f mm, tolerance %.3f mm, %.1f s\n", steered * 1e3, v.executed_miss * 1e3,
              v.planned_miss * 1e3, v.tip_gap * 1e3, v.tip_motion * 1e3, v.channel_gap * 1e3, v.target_motion * 1e3,
              tol * 1e3, v.seconds);
  EXPECT_GT(steered, 10e-3);
  EXPECT_LE(v.tip_gap, tol);
  EXPECT_LE(std::abs(v.executed_miss - v.planned_miss), tol + v.target_motion);
  EXPECT_LE(v.tip_gap, v.tip_motion + v.channel_gap + 1e-12);  // the gap's two parts
}

TEST(Planner, ChooseRiskTakesThePlanWithTheLowestObstacleTouchProbability) {
  const Scenario sc = scenarioWith("  target: tumour\n  avoid:\n    - {inclusion: vessel, clearance: 0.5 mm}\n"
                                   "  entry_window: 15 mm\n  max_entry_angle: 15 deg\n  choose: risk\n"
                                   "  uncertainty: {samples: 300, entry_sd: 1 mm, angle_sd: 1 deg, curvature_sd: 0.1}\n");
  const PlanOutcome o = planScenario(sc);
  ASSERT_TRUE(o.search.feasible) << o.search.reason;
  ASSERT_GT(o.search.found.size(), 1u);
  EXPECT_EQ(o.chosen_by, "risk");
  const ErrorDistribution chosen = openLoopErrors(o.problem, o.search.best.plan, sc.plan.uncertainty);
  for (const CheckedPath& p : o.search.found) {
    const ErrorDistribution e = openLoopErrors(o.problem, p.plan, sc.plan.uncertainty);
    EXPECT_GE(e.touch_probability, chosen.touch_probability);
  }
}
