// The needlesim command line end to end: run, check, schema, --version, and
// the exit codes and messages a user sees for bad input.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <sys/wait.h>

#include "needlesim/io/checkpoint.hpp"

namespace fs = std::filesystem;

namespace {

struct Result {
  int code;
  std::string out;  // stdout and stderr together
};

Result runCli(const std::string& args) {
  std::string cmd = std::string(NEEDLESIM_BINARY) + " " + args + " 2>&1";
  Result r{-1, {}};
  FILE* p = popen(cmd.c_str(), "r");
  if (!p) return r;
  std::array<char, 4096> buf{};
  while (fgets(buf.data(), buf.size(), p)) r.out += buf.data();
  int status = pclose(p);
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

fs::path scratch(const std::string& name) {
  fs::path d = fs::temp_directory_path() / ("needlesim_cli_" + std::to_string(::getpid())) / name;
  fs::remove_all(d);
  fs::create_directories(d.parent_path());
  return d;
}

std::string example(const std::string& f) { return std::string(NEEDLESIM_SOURCE_DIR) + "/examples/" + f; }

}  // namespace

TEST(Cli, VersionAndHelp) {
  auto v = runCli("--version");
  EXPECT_EQ(v.code, 0);
  EXPECT_NE(v.out.find("needlesim 0."), std::string::npos);
  auto h = runCli("--help");
  EXPECT_EQ(h.code, 0);
  for (const char* c : {"run", "check", "schema"}) EXPECT_NE(h.out.find(c), std::string::npos) << c;
}

TEST(Cli, RunWritesSummaryCsvAndSelfContainedReport) {
  fs::path out = scratch("run");
  auto r = runCli("run " + example("gelatin_18G_3mms.yaml") + " --quiet --out " + out.string());
  ASSERT_EQ(r.code, 0) << r.out;
  ASSERT_TRUE(fs::exists(out / "summary.json"));
  ASSERT_TRUE(fs::exists(out / "forces.csv"));
  ASSERT_TRUE(fs::exists(out / "report.html"));
  nlohmann::json s = nlohmann::json::parse(std::ifstream(out / "summary.json"));
  EXPECT_EQ(s["engine"], "lumped");
  EXPECT_EQ(s["scenario"]["tissue"]["block"]["length"], "0.055 m");  // as understood: SI with its unit
  EXPECT_TRUE(s["needlesim"].contains("git_revision"));
  // Exit force at 3 mm/s: 0.04335 + 0.055 (3.791 + 285.053 x 0.003) N (seed 003 eq 5.1).
  double expected = 0.04335 + 0.055 * (3.791 + 285.053 * 0.003);
  EXPECT_NEAR(s["results"]["exit_force"]["value"].get<double>(), expected, 2e-3 * expected);
  std::ifstream csv(out / "forces.csv");
  std::string header;
  std::getline(csv, header);
  EXPECT_EQ(header.rfind("time [s],depth [m],velocity [m/s],force_total [N]", 0), 0u) << header;
  std::string html((std::istreambuf_iterator<char>(std::ifstream(out / "report.html").rdbuf())), {});
  EXPECT_NE(html.find("new Chart("), std::string::npos);
  EXPECT_EQ(html.find("<script src="), std::string::npos);  // nothing fetched from the network
  EXPECT_EQ(html.find("<link "), std::string::npos);
}

TEST(Cli, ExistingResultsFolderIsNeverSilentlyOverwritten) {
  fs::path out = scratch("keep");
  fs::create_directories(out);
  std::ofstream(out / "mine.txt") << "user data";
  auto r = runCli("run " + example("gelatin_18G_3mms.yaml") + " --quiet --out " + out.string());
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.out.find("already exists"), std::string::npos) << r.out;
  EXPECT_TRUE(fs::exists(out / "mine.txt"));
  auto again = runCli("run " + example("gelatin_18G_3mms.yaml") + " --quiet --overwrite --out " + out.string());
  EXPECT_EQ(again.code, 0) << again.out;
  EXPECT_TRUE(fs::exists(out / "summary.json"));
}

TEST(Cli, CheckAcceptsExamplesAndRejectsBadFilesWithExitCode2) {
  auto ok = runCli("check " + example("gelatin_18G_3mms.yaml") + " " + example("layered_skin_fat_muscle.yaml"));
  EXPECT_EQ(ok.code, 0) << ok.out;
  fs::path bad = scratch("bad.yaml");
  std::ofstream(bad) << "tissue:\n  block: {length: 55 mm, width: 1 m, height: 1 m}\n"
                        "  material: {law: linear, E: -3 kPa, nu: 0.4}\n"
                        "needle: {outer_diameter: 18 G, length: 150 mm}\n"
                        "insertion: {profile: [{insert: {to: 10 mm, speed: 1 mm/s}}]}\n";
  auto r = runCli("check " + bad.string());
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.out.find(bad.string() + ":3:"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("tissue.material.E"), std::string::npos) << r.out;
  auto missing = runCli("check /no/such/file.yaml");
  EXPECT_EQ(missing.code, 2);
  auto badArg = runCli("run --frobnicate");
  EXPECT_NE(badArg.code, 0);
}

TEST(Cli, SchemaListsEveryFieldWithUnits) {
  auto r = runCli("schema");
  EXPECT_EQ(r.code, 0);
  for (const char* f : {"outer_diameter", "static_band", "puncture", "entry_angle", "time_step"})
    EXPECT_NE(r.out.find(f), std::string::npos) << f;
}

// Every scenario and study shipped in examples/ is valid (studies: their representative cases;
// tests/study/field_path_test.cpp reads every case).
// summary.json holds the whole scenario as understood: running the summary itself
// gives the same results, byte for byte.
TEST(Cli, ARunFromItsOwnSummaryGivesTheSameResults) {
  fs::path first = scratch("first"), again = scratch("again");
  auto r = runCli("run " + example("layered_skin_fat_muscle.yaml") + " --quiet --out " + first.string());
  ASSERT_EQ(r.code, 0) << r.out;
  r = runCli("run " + (first / "summary.json").string() + " --quiet --out " + again.string());
  ASSERT_EQ(r.code, 0) << r.out;
  auto text = [](const fs::path& p) {
    return std::string((std::istreambuf_iterator<char>(std::ifstream(p).rdbuf())), {});
  };
  EXPECT_EQ(text(first / "forces.csv"), text(again / "forces.csv"));
  nlohmann::json a = nlohmann::json::parse(std::ifstream(first / "summary.json"));
  nlohmann::json b = nlohmann::json::parse(std::ifstream(again / "summary.json"));
  EXPECT_EQ(a["scenario"], b["scenario"]);
  EXPECT_EQ(a["results"], b["results"]);
  for (const char* section : {"tissue", "needle", "insertion", "model", "output"})
    EXPECT_TRUE(a["scenario"].contains(section)) << section;
  for (const char* engine : {"lumped", "realtime2d", "steering", "mpm", "explicit"})
    EXPECT_TRUE(a["scenario"]["model"].contains(engine)) << engine;
  EXPECT_TRUE(a["scenario"]["output"].contains("checkpoint_interval"));
}

TEST(Cli, EveryShippedExampleAndStudyPassesCheck) {
  std::string args;
  int n = 0;
  for (const auto& e : fs::recursive_directory_iterator(std::string(NEEDLESIM_SOURCE_DIR) + "/examples"))
    if (e.path().extension() == ".yaml") {
      args += " " + e.path().string();
      ++n;
    }
  ASSERT_GT(n, 10);
  auto r = runCli("check" + args);
  EXPECT_EQ(r.code, 0) << r.out;
  auto bad = runCli("check " + example("gelatin_18G_3mms.yaml") + " /no/such.yaml");
  EXPECT_EQ(bad.code, 2);
  EXPECT_NE(bad.out.find("1 of 2 files"), std::string::npos) << bad.out;
}

// needlesim run --resume (io/checkpoint.hpp): every refusal is an input error
// (exit code 2) naming the file; the bit-identical resume itself is tested in
// tests/mpm/test_mpm_checkpoint.cpp.
TEST(Cli, ResumeRefusalsExitWithCode2AndNameTheFile) {
  auto lumped = runCli("run " + example("gelatin_18G_3mms.yaml") + " --quiet --resume --out " + scratch("lumped").string());
  EXPECT_EQ(lumped.code, 2) << lumped.out;
  EXPECT_NE(lumped.out.find("does not write checkpoints"), std::string::npos) << lumped.out;

  const fs::path out = scratch("mpm_resume");
  const std::string run = "run " + example("mpm/quick_needle_block.yaml") + " --quiet --out " + out.string();
  const fs::path ck = out.string() + ".checkpoint";
  fs::remove_all(ck);
  auto none = runCli(run + " --resume");
  EXPECT_EQ(none.code, 2) << none.out;
  EXPECT_NE(none.out.find((ck / "state.bin").string()), std::string::npos) << none.out;
  EXPECT_NE(none.out.find("no checkpoint to resume"), std::string::npos) << none.out;

  fs::create_directories(ck);
  std::ofstream(ck / "state.bin") << "NSSTATE\n\x03";  // cut short after the magic
  auto damaged = runCli(run + " --resume");
  EXPECT_EQ(damaged.code, 2) << damaged.out;
  EXPECT_NE(damaged.out.find("state.bin: truncated"), std::string::npos) << damaged.out;
  // A fresh run does not silently discard the checkpoint of an interrupted one.
  auto fresh = runCli(run);
  EXPECT_EQ(fresh.code, 2) << fresh.out;
  EXPECT_NE(fresh.out.find("--resume"), std::string::npos) << fresh.out;
  EXPECT_TRUE(fs::exists(ck / "state.bin"));
  EXPECT_FALSE(fs::exists(out));
  fs::remove_all(ck);
}

TEST(Cli, AbandonedStagingFoldersOfDeadRunsAreFound) {
  const fs::path dir = scratch("stages");
  fs::create_directories(dir);
  const pid_t child = fork();  // a process that has ended: its pid is free
  if (child == 0) _exit(0);
  ASSERT_GT(child, 0);
  waitpid(child, nullptr, 0);
  const std::string dead = std::to_string(child);
  const pid_t zombie = fork();  // ended but not collected yet (a killed run before init reaps it)
  if (zombie == 0) _exit(0);
  ASSERT_GT(zombie, 0);
  usleep(200000);
  fs::create_directories(dir / (".res-3.partial-" + std::to_string(zombie)));
  for (const std::string n : {".res.partial-" + dead, ".res-2.partial-" + dead, ".res.partial-" + std::to_string(::getpid()),
                              ".other.partial-" + dead, ".res-x.partial-" + dead})
    fs::create_directories(dir / n);
  EXPECT_EQ(needlesim::io::removeAbandonedStages(dir / "res"), 3);
  waitpid(zombie, nullptr, 0);
  EXPECT_FALSE(fs::exists(dir / (".res-3.partial-" + std::to_string(zombie))));
  EXPECT_FALSE(fs::exists(dir / (".res.partial-" + dead)));
  EXPECT_FALSE(fs::exists(dir / (".res-2.partial-" + dead)));
  EXPECT_TRUE(fs::exists(dir / (".res.partial-" + std::to_string(::getpid()))));  // a live process
  EXPECT_TRUE(fs::exists(dir / (".other.partial-" + dead)));                     // another target
  EXPECT_TRUE(fs::exists(dir / (".res-x.partial-" + dead)));
  fs::remove_all(dir);
}

// Engines that do not model embedded bodies refuse a scenario with inclusions in
// check and run alike, naming the field and the engines that can.
TEST(Cli, AnEngineWithoutInclusionsRefusesThemInCheckAndRun) {
  fs::path dir = scratch("inclusion");
  fs::create_directories(dir);
  std::ifstream in(example("gelatin_18G_3mms.yaml"));
  std::string yaml((std::istreambuf_iterator<char>(in)), {});
  const std::string at = "tissue:\n";
  const auto pos = yaml.find(at);
  ASSERT_NE(pos, std::string::npos);
  yaml.insert(pos + at.size(), "  inclusions:\n    - {name: tumour, depth: 20 mm, radius: 4 mm, material: {law: linear, E: 90 kPa, nu: 0.45}}\n");
  std::ofstream(dir / "with_tumour.yaml") << yaml;
  for (const char* cmd : {"check ", "run --quiet "}) {
    auto r = runCli(cmd + (dir / "with_tumour.yaml").string());
    EXPECT_EQ(r.code, 2) << r.out;
    EXPECT_NE(r.out.find("tissue.inclusions"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("engine lumped does not model"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("mpm"), std::string::npos) << r.out;
  }
}
