// needlesim check on scenarios whose tissue.geometry is a Gmsh script that would act (Exit,
// SystemCall) or exceed the meshing budgets (tissue.geometry.max_elements, max_mesh_time):
// refused with exit code 2 naming the file and line or the budget, and the next file is checked.
#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <csignal>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "cli_run.hpp"

namespace fs = std::filesystem;
using needlesim::test::runCli;

namespace {

fs::path scratchDir() {
  const auto dir = fs::temp_directory_path() / ("needlesim_geometry_cli_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  return dir;
}

std::string slurp(const fs::path& p) {
  std::stringstream s;
  s << std::ifstream(p).rdbuf();
  return s.str();
}

fs::path example(const std::string& rel) { return fs::path(NEEDLESIM_SOURCE_DIR) / "examples" / rel; }

// The realtime2d imported-block example beside its script, the script followed by `tail`, the
// scenario's geometry section given `extra` keys.
fs::path blockScenario(const std::string& name, const std::string& tail, const std::string& extra = "") {
  const auto dir = scratchDir();
  std::ofstream(dir / (name + ".geo")) << slurp(example("realtime2d/imported_block.geo")) << tail;
  std::string yaml = slurp(example("realtime2d/imported_block.yaml"));
  const std::string from = "geometry: {file: imported_block.geo, unit: mm}";
  yaml.replace(yaml.find(from), from.size(), "geometry: {file: " + name + ".geo, unit: mm" + extra + "}");
  std::ofstream(dir / (name + ".yaml")) << yaml;
  return dir / (name + ".yaml");
}

}  // namespace

TEST(GeometryCli, AScriptThatExitsIsRefusedAndTheNextFileIsStillChecked) {
  const auto exits = blockScenario("exits", "Exit;\n");  // the line after the example script's last
  const auto runs = blockScenario("runs", "SystemCall \"touch PWNED\";\n");
  const std::string script = slurp(example("realtime2d/imported_block.geo"));
  const std::string line = ":" + std::to_string(std::count(script.begin(), script.end(), '\n') + 1) + ":";
  const auto good = example("gelatin_18G_3mms.yaml");
  const auto r = runCli("check " + exits.string() + " " + runs.string() + " " + good.string());
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find("exits.geo" + line), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("runs.geo" + line), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("2 of 3 files"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("gelatin_18G_3mms.yaml: ok"), std::string::npos) << r.out;  // the third was checked
  EXPECT_FALSE(fs::exists(exits.parent_path() / "PWNED"));
  const auto fine = runCli("check " + blockScenario("fine", "").string());
  EXPECT_EQ(fine.code, 0) << fine.out;
}

TEST(GeometryCli, MeshingBudgetsAreScenarioFields) {
  // an element size a thousandth of the shipped prostate script's: refused before meshing
  const auto dir = scratchDir();
  fs::copy_file(example("anatomy/prostate_tumour.geo"), dir / "prostate_tumour.geo", fs::copy_options::overwrite_existing);
  std::string yaml = slurp(example("anatomy/prostate_tumour_explicit.yaml"));
  yaml.replace(yaml.find("    unit: mm"), 12, "    unit: mm\n    element_size: 0.001 mm");
  std::ofstream(dir / "fine_prostate.yaml") << yaml;
  const auto start = std::chrono::steady_clock::now();
  const auto fine = runCli("check " + (dir / "fine_prostate.yaml").string());
  EXPECT_EQ(fine.code, 2) << fine.out;
  EXPECT_NE(fine.out.find("more than tissue.geometry.max_elements (2e+06)"), std::string::npos) << fine.out;
  // a script looping for ever, stopped at the scenario's time budget
  const auto loops = blockScenario("loops", "For i In {1:2000000000}\n  x = i;\nEndFor\n", ", max_mesh_time: 2 s");
  const auto slow = runCli("check " + loops.string());
  EXPECT_EQ(slow.code, 2) << slow.out;
  EXPECT_NE(slow.out.find("max_mesh_time (2 s)"), std::string::npos) << slow.out;
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 40.0);
}

TEST(GeometryCli, CtrlCWhileAScriptIsMeshedStopsTheRunWithinASecond) {
  const auto loops = blockScenario("stops", "For i In {1:2000000000}\n  x = i;\nEndFor\n");
  const auto log = loops.parent_path() / "stops.log";
  const pid_t pid =
      needlesim::test::startCli("run " + loops.string() + " --out " + (loops.parent_path() / "stops_out").string(), log);
  ::sleep(2);  // reading the scenario, the script looping in the reader
  const auto asked = std::chrono::steady_clock::now();
  ::kill(pid, SIGINT);
  int status = 0;
  ::waitpid(pid, &status, 0);
  const double took = std::chrono::duration<double>(std::chrono::steady_clock::now() - asked).count();
  ASSERT_TRUE(WIFEXITED(status)) << slurp(log);
  EXPECT_EQ(WEXITSTATUS(status), 130) << slurp(log);
  EXPECT_NE(slurp(log).find("stops.geo: interrupted by SIGINT"), std::string::npos) << slurp(log);
  EXPECT_LT(took, 1.0);
  EXPECT_FALSE(fs::exists(loops.parent_path() / "stops_out"));
}
