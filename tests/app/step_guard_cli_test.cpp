// The step guards and the run budget (engines/step_guard.hpp) as a user meets
// them: `run` and `check` refuse, with exit code 2, a profile the steps do not
// resolve and a run above output.max_steps, before any step, and print the
// estimate of the runs they accept.
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <unistd.h>

#include "cli_run.hpp"

namespace fs = std::filesystem;
using needlesim::test::runCli;

namespace {

fs::path scratch(const std::string& name) {
  fs::path d = fs::temp_directory_path() / ("needlesim_guard_" + std::to_string(::getpid())) / name;
  fs::remove_all(d);
  fs::create_directories(d.parent_path());
  return d;
}

std::string example(const std::string& f) { return std::string(NEEDLESIM_SOURCE_DIR) + "/examples/" + f; }

// An example's text with `from` replaced by `to`, written as a scratch file.
std::string edited(const std::string& file, const std::string& from, const std::string& to, const std::string& name) {
  std::stringstream in;
  in << std::ifstream(example(file)).rdbuf();
  std::string text = in.str();
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) text.replace(at, from.size(), to);
  const fs::path p = scratch(name);
  std::ofstream(p) << text;
  return p.string();
}

void expectHas(const std::string& out, std::initializer_list<const char*> words) {
  for (const char* w : words) EXPECT_NE(out.find(w), std::string::npos) << "missing '" << w << "' in:\n" << out;
}

}  // namespace

// 100 m/s to 20 mm: 0.2 ms of motion against the 1 ms step. Before the guard
// the run gave all-zero forces marked complete.
TEST(StepGuardCli, LumpedInsertFasterThanAStepIsRefusedByRunAndCheck) {
  const std::string f = edited("gelatin_18G_3mms.yaml", "- insert: {to: 70 mm, speed: 3 mm/s}",
                               "- insert: {to: 20 mm, speed: 100 m/s}", "lumped_fast.yaml");
  const fs::path out = scratch("lumped_fast");
  auto run = runCli("run " + f + " --quiet --out " + out.string());
  EXPECT_EQ(run.code, 2) << run.out;
  expectHas(run.out, {"lumped_fast.yaml:34:", "insertion.profile[0].insert.speed", "'100 m/s'", "moves the needle 100 mm per time step of 1 ms",
                      "at most 2 m/s at this step", "model.time_step at most 20 us"});
  EXPECT_FALSE(fs::exists(out));
  auto check = runCli("check " + f);
  EXPECT_EQ(check.code, 2) << check.out;
  expectHas(check.out, {"lumped_fast.yaml:34:", "insertion.profile[0].insert.speed", "'100 m/s'"});
}

// The same insert as the whole profile: the 1 ms step is longer than all of it, named by model.time_step.
TEST(StepGuardCli, AStepLongerThanTheWholeMotionIsNamedByItsField) {
  const fs::path f = scratch("lumped_only_fast.yaml");
  std::ofstream(f) << "tissue:\n  block: {length: 55 mm, width: 120 mm, height: 80 mm}\n  material: gelatin_10wt\n"
                      "needle: {outer_diameter: 18 G, length: 150 mm}\n"
                      "insertion: {profile: [{insert: {to: 20 mm, speed: 100 m/s}}]}\n";
  auto r = runCli("run " + f.string() + " --quiet --out " + scratch("lumped_only_fast").string());
  EXPECT_EQ(r.code, 2) << r.out;
  expectHas(r.out, {"model.time_step", "'1 ms'", "longer than the whole 200 us motion", "model.time_step at most 20 us",
                    "insertion.profile[0].insert.speed at most 2 m/s"});
}

// The quick mpm example at 50 m/s: the 5.5 mm profile lasts 0.11 ms, the first stable step 2.35 ms.
TEST(StepGuardCli, MpmQuickExampleAt50MetresPerSecondIsRefused) {
  const std::string f = edited("mpm/quick_needle_block.yaml", "speed: 6 mm/s", "speed: 50 m/s", "mpm_fast.yaml");
  auto r = runCli("run " + f + " --quiet --out " + scratch("mpm_fast").string());
  EXPECT_EQ(r.code, 2) << r.out;
  expectHas(r.out, {"model.mpm.mass_scaling", "eqs 25-26", "longer than the whole 110 us motion",
                    "insertion.profile[0].insert.speed at most"});
}

// mass_scaling 1e12 (the schema allows it) gave one 23.5 s step for the 0.917 s profile.
TEST(StepGuardCli, MpmMassScaling1e12IsRefusedNamingTheField) {
  const std::string f =
      edited("mpm/quick_needle_block.yaml", "mass_scaling: 1e4", "mass_scaling: 1e12", "mpm_scaled.yaml");
  auto r = runCli("check " + f);
  EXPECT_EQ(r.code, 2) << r.out;
  expectHas(r.out, {"model.mpm.mass_scaling", "'1e+12'", "time step 23.5 s", "917 ms motion",
                    "model.mpm.mass_scaling at most 1.3e+07"});
}

// nu 0.4999999: the wave speed, and so the step count, grows by ~500 (the run takes minutes, not a second).
// Refused within the budget before the first particle is placed, with the estimate.
TEST(StepGuardCli, NearlyIncompressibleQuickMpmIsRefusedFastWithItsEstimate) {
  std::string f = edited("mpm/quick_needle_block.yaml", "nu: 0.475", "nu: 0.4999999", "mpm_nu.yaml");
  auto check = runCli("check " + f);  // within the default budget of 1e6 steps: accepted, with its estimate
  EXPECT_EQ(check.code, 0) << check.out;
  expectHas(check.out, {"estimate: at least 1.6e+05 steps x 2304 points, about "});
  f = edited("mpm/quick_needle_block.yaml", "nu: 0.475", "nu: 0.4999999", "mpm_nu_budget.yaml");
  std::ofstream(f, std::ios::app) << "  max_steps: 1e5\n";  // the last section is output:
  const auto t0 = std::chrono::steady_clock::now();
  auto r = runCli("run " + f + " --quiet --out " + scratch("mpm_nu").string());
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_LT(seconds, 2.0);
  expectHas(r.out, {"output.max_steps", "'100000'", "at least 1.6e+05 steps x 2304 points, about ",
                    "output.max_steps of at least 1.7e+05", "nu further from 0.5", "mass_scaling"});
}

TEST(StepGuardCli, ANormalRunPrintsItsEstimateAndRuns) {
  auto r = runCli("run " + example("mpm/quick_needle_block.yaml") + " --out " + scratch("quick").string());
  EXPECT_EQ(r.code, 0) << r.out;
  expectHas(r.out, {"estimate: at least 391 steps x 2304 points, about ", "peak_force"});
  auto check = runCli("check " + example("gelatin_18G_3mms.yaml"));
  EXPECT_EQ(check.code, 0) << check.out;
  expectHas(check.out, {"estimate: 53334 steps, about "});
}
