// Messages that point the user the right way: a study given to `run`, a misspelt library
// material, a missing mesh file (the scenario's line and the absolute path looked at), and
// `check` on folders (every *.yaml below them, sorted).
#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "cli_run.hpp"

namespace fs = std::filesystem;
using needlesim::test::runCli;
using needlesim::test::runShell;

namespace {

fs::path scratch(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("needlesim_guidance_cli_" + std::to_string(::getpid())) / name;
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

fs::path example(const std::string& rel) { return fs::path(NEEDLESIM_SOURCE_DIR) / "examples" / rel; }

std::string slurp(const fs::path& p) {
  std::stringstream s;
  s << std::ifstream(p).rdbuf();
  return s.str();
}

// `example` with `from` replaced by `to`, written to `file`.
void edited(const std::string& rel, const std::string& from, const std::string& to, const fs::path& file) {
  std::string yaml = slurp(example(rel));
  const auto at = yaml.find(from);
  ASSERT_NE(at, std::string::npos) << from;
  yaml.replace(at, from.size(), to);
  fs::create_directories(file.parent_path());
  std::ofstream(file) << yaml;
}

// The 1-based line of `file` that contains `part`.
int lineWith(const fs::path& file, const std::string& part) {
  std::ifstream in(file);
  std::string line;
  for (int n = 1; std::getline(in, line); ++n)
    if (line.find(part) != std::string::npos) return n;
  return 0;
}

}  // namespace

TEST(CliGuidance, RunOnAStudySaysItIsAStudyAndNamesSweep) {
  const fs::path study = example("studies/friction_speed_grid.yaml");
  const auto r = runCli("run " + study.string() + " --out " + (scratch("study") / "out").string());
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find(study.string() + ":" + std::to_string(lineWith(study, "scenario:")) + ":"), std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("this file a study"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("needlesim sweep"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("is not a known field"), std::string::npos) << r.out;
}

TEST(CliGuidance, AMisspeltLibraryMaterialGetsTheNearestName) {
  const fs::path dir = scratch("material");
  edited("gelatin_18G_3mms.yaml", "material: gelatin_10wt", "material: gelatine_10wt", dir / "named.yaml");
  edited("gelatin_18G_3mms.yaml", "material: gelatin_10wt", "material: {base: porcine_gell}", dir / "base.yaml");
  const auto named = runCli("check " + (dir / "named.yaml").string());
  EXPECT_EQ(named.code, 2) << named.out;
  EXPECT_NE(named.out.find("did you mean 'gelatin_10wt'?"), std::string::npos) << named.out;
  const auto base = runCli("check " + (dir / "base.yaml").string());
  EXPECT_EQ(base.code, 2) << base.out;
  EXPECT_NE(base.out.find("did you mean 'porcine_gel'?"), std::string::npos) << base.out;
}

// The scenario is named relative to the working folder; the mesh path relative to the scenario.
TEST(CliGuidance, AMissingMeshNamesTheScenarioLineAndTheAbsolutePathLookedAt) {
  const fs::path dir = scratch("mesh");
  edited("anatomy/prostate_tumour_mpm.yaml", "file: prostate_tumour.geo", "file: meshes/gone.msh", dir / "s.yaml");
  const auto r = runShell("cd '" + dir.string() + "' && " + NEEDLESIM_BINARY + " check s.yaml");
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find("s.yaml:" + std::to_string(lineWith(dir / "s.yaml", "file: meshes/gone.msh")) + ":"),
            std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("tissue.geometry.file"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find((fs::canonical(dir) / "meshes" / "gone.msh").string()), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("does not exist"), std::string::npos) << r.out;
}

TEST(CliGuidance, CheckOnAFolderChecksEveryYamlBelowItSorted) {
  const fs::path dir = scratch("folder");
  for (const char* f : {"b/two.yaml", "a/sub/three.yaml", "a/one.yaml"}) {
    fs::create_directories((dir / f).parent_path());
    fs::copy_file(example("gelatin_18G_3mms.yaml"), dir / f);
  }
  std::ofstream(dir / "a" / "notes.txt") << "not a scenario\n";
  const auto r = runCli("check " + dir.string());
  EXPECT_EQ(r.code, 0) << r.out;
  const auto one = r.out.find((dir / "a/one.yaml").string() + ": ok");
  const auto three = r.out.find((dir / "a/sub/three.yaml").string() + ": ok");
  const auto two = r.out.find((dir / "b/two.yaml").string() + ": ok");
  ASSERT_NE(one, std::string::npos) << r.out;
  ASSERT_NE(three, std::string::npos) << r.out;
  ASSERT_NE(two, std::string::npos) << r.out;
  EXPECT_LT(one, three);
  EXPECT_LT(three, two);
  EXPECT_EQ(r.out.find("notes.txt"), std::string::npos) << r.out;

  const fs::path empty = scratch("empty");
  const auto none = runCli("check " + empty.string());
  EXPECT_EQ(none.code, 2) << none.out;
  EXPECT_NE(none.out.find("no .yaml file"), std::string::npos) << none.out;
}

// The README's `needlesim check examples/`: every shipped scenario and study, as the tree holds them.
TEST(CliGuidance, CheckExamplesChecksEveryShippedFile) {
  int shipped = 0;
  for (const auto& e : fs::recursive_directory_iterator(example("")))
    if (e.path().extension() == ".yaml") ++shipped;
  ASSERT_GT(shipped, 10);
  const auto r = runShell(std::string("cd '") + NEEDLESIM_SOURCE_DIR + "' && " + NEEDLESIM_BINARY + " check examples/");
  EXPECT_EQ(r.code, 0) << r.out;
  int ok = 0;
  for (std::size_t at = r.out.find(": ok ("); at != std::string::npos; at = r.out.find(": ok (", at + 1)) ++ok;
  EXPECT_EQ(ok, shipped) << r.out;
}
