// The needlesim command line end to end: run, check, schema, --version, and
// the exit codes and messages a user sees for bad input.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <vector>

#include "needlesim/results/checkpoint.hpp"
#include "needlesim/results/results_folder.hpp"
#include "cli_run.hpp"

namespace fs = std::filesystem;

namespace {

using needlesim::test::runCli;
using needlesim::test::runShell;
using needlesim::test::startCli;

// Waits for `pid` (at most `seconds`, then kills it): its exit code, or -signal.
int waitFor(pid_t pid, double seconds) {
  int status = 0;
  for (int i = 0; i < seconds * 20; ++i) {
    if (waitpid(pid, &status, WNOHANG) == pid) return WIFEXITED(status) ? WEXITSTATUS(status) : -WTERMSIG(status);
    usleep(50000);
  }
  kill(pid, SIGKILL);
  waitpid(pid, &status, 0);
  return -1000;
}

// Whether `path` appears within `seconds`.
bool appears(const fs::path& path, double seconds) {
  for (int i = 0; i < seconds * 20; ++i) {
    if (fs::exists(path)) return true;
    usleep(50000);
  }
  return false;
}

std::string text(const fs::path& p) { return std::string((std::istreambuf_iterator<char>(std::ifstream(p).rdbuf())), {}); }

// `example` with `from` replaced by `to` (once), written to `file`.
void editedExample(const std::string& example, const std::string& from, const std::string& to, const fs::path& file) {
  std::string yaml = text(std::string(NEEDLESIM_SOURCE_DIR) + "/examples/" + example);
  const auto at = yaml.find(from);
  ASSERT_NE(at, std::string::npos) << from;
  yaml.replace(at, from.size(), to);
  fs::create_directories(file.parent_path());
  std::ofstream(file) << yaml;
}

// The entries of `dir` whose name contains `part`.
std::vector<std::string> entriesWith(const fs::path& dir, const std::string& part) {
  std::vector<std::string> out;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.path().filename().string().find(part) != std::string::npos) out.push_back(e.path().filename().string());
  return out;
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
  // --overwrite replaces only a results folder needlesim wrote: refused before the run, the file stays.
  auto again = runCli("run " + example("gelatin_18G_3mms.yaml") + " --quiet --overwrite --out " + out.string());
  EXPECT_EQ(again.code, 2) << again.out;
  EXPECT_NE(again.out.find("--out: is a folder holding mine.txt, not a needlesim results folder"), std::string::npos)
      << again.out;
  EXPECT_NE(again.out.find("--overwrite replaces only a folder written by needlesim"), std::string::npos) << again.out;
  EXPECT_TRUE(fs::exists(out / "mine.txt"));
  EXPECT_FALSE(fs::exists(out / "summary.json"));
  std::ofstream(out.string() + ".txt") << "a file, not a folder";
  auto file = runCli("run " + example("gelatin_18G_3mms.yaml") + " --quiet --overwrite --out " + out.string() + ".txt");
  EXPECT_EQ(file.code, 2) << file.out;
  EXPECT_NE(file.out.find("is a file, not a needlesim results folder"), std::string::npos) << file.out;
  // A results folder of an earlier run is replaced.
  fs::path res = scratch("keep_results");
  ASSERT_EQ(runCli("run " + example("gelatin_18G_3mms.yaml") + " --quiet --out " + res.string()).code, 0);
  auto replaced = runCli("run " + example("gelatin_18G_3mms.yaml") + " --quiet --overwrite --out " + res.string());
  EXPECT_EQ(replaced.code, 0) << replaced.out;
  EXPECT_TRUE(fs::exists(res / "summary.json"));
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
// An OpenMP engine runs with OpenMP's spin shortened (the CLI starts again with GOMP_SPINCOUNT set,
// openmp_wait.cpp), an engine without OpenMP as started, and a caller's own setting is kept;
// summary.json says which ran.
TEST(Cli, OpenMpEnginesRunWithAShortSpinUnlessTheCallerChose) {
  const std::string bin = std::string(NEEDLESIM_BINARY);
  const auto waitOf = [&](const std::string& env, const std::string& file, const std::string& name) {
    fs::path out = scratch(name);
    auto r = runShell("env -u GOMP_SPINCOUNT -u OMP_WAIT_POLICY " + env + " " + bin + " run " +
                      (file.ends_with(".json") ? file : example(file)) + " --quiet --out " + out.string());
    EXPECT_EQ(r.code, 0) << r.out;
    return nlohmann::json::parse(std::ifstream(out / "summary.json"))["needlesim"]["openmp_wait"].get<std::string>();
  };
  EXPECT_EQ(waitOf("", "mpm/quick_needle_block.yaml", "omp_mpm"), "GOMP_SPINCOUNT=1000");
  EXPECT_EQ(waitOf("", "gelatin_18G_3mms.yaml", "omp_lumped").rfind("libgomp's default", 0), 0u);
  EXPECT_EQ(waitOf("OMP_WAIT_POLICY=passive", "mpm/quick_needle_block.yaml", "omp_kept"), "OMP_WAIT_POLICY=passive");
  // a run from a results folder's summary.json: the engine it records
  const fs::path record = scratch("omp_record").parent_path() / "omp_mpm" / "summary.json";
  EXPECT_EQ(waitOf("", record.string(), "omp_record"), "GOMP_SPINCOUNT=1000");
}

// summary.json holds the whole scenario as understood: running the summary itself
// gives the same results, byte for byte.
TEST(Cli, ARunFromItsOwnSummaryGivesTheSameResults) {
  fs::path first = scratch("first"), again = scratch("again");
  auto r = runCli("run " + example("layered_skin_fat_muscle.yaml") + " --quiet --out " + first.string());
  ASSERT_EQ(r.code, 0) << r.out;
  r = runCli("run " + (first / "summary.json").string() + " --quiet --out " + again.string());
  ASSERT_EQ(r.code, 0) << r.out;
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

// needlesim run --resume (results/checkpoint.hpp): every refusal is an input error
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

TEST(Cli, StaleStagingFoldersOfDeadRunsAreFound) {
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
  for (const std::string n : {".res.partial-" + dead, ".other.partial-" + dead, ".res.partial-" + std::to_string(::getpid()),
                              "res.partial-" + dead, ".partial-" + dead, ".res.partial-" + dead + "x"})
    fs::create_directories(dir / n);
  std::ofstream(dir / (".file.partial-" + dead)) << "a user's file, not a staging folder";
  EXPECT_EQ(needlesim::io::removeStaleStages(dir), 3);
  waitpid(zombie, nullptr, 0);
  EXPECT_FALSE(fs::exists(dir / (".res-3.partial-" + std::to_string(zombie))));
  EXPECT_FALSE(fs::exists(dir / (".res.partial-" + dead)));
  EXPECT_FALSE(fs::exists(dir / (".other.partial-" + dead)));
  EXPECT_TRUE(fs::exists(dir / (".res.partial-" + std::to_string(::getpid()))));  // a live process
  EXPECT_TRUE(fs::exists(dir / ("res.partial-" + dead)));                        // not hidden: not a stage
  EXPECT_TRUE(fs::exists(dir / (".partial-" + dead)));                           // no name
  EXPECT_TRUE(fs::exists(dir / (".res.partial-" + dead + "x")));                 // not a pid
  EXPECT_TRUE(fs::exists(dir / (".file.partial-" + dead)));                      // a file
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

// A disk that fills during a run with field output (HDF5) is one clean error
// naming the file; nothing is committed, nothing is left behind.
TEST(Cli, AFullDiskIsOneCleanErrorAndCommitsNothing) {
  const fs::path dir = scratch("full_disk");
  fs::create_directories(dir);
  for (const std::string ex :
       {"mpm/quick_needle_block.yaml", "explicit/target_inclusion_2d.yaml", "realtime2d/layered_target.yaml"}) {
    for (const int kib : {8, 200}) {
      if (ex.starts_with("realtime2d") && kib > 8) continue;  // 4 s a run: one size is enough
      auto r = runShell("cd " + dir.string() + " && ulimit -f " + std::to_string(kib) + " && trap '' XFSZ && " +
                        NEEDLESIM_BINARY + " run " + example(ex) + " --quiet --out full");
      EXPECT_EQ(r.code, 1) << ex << " " << kib << " KiB: " << r.out;  // an error, not a crash (a signal gives < 0)
      EXPECT_NE(r.out.find(".h5: disk full / write failed: File too large"), std::string::npos) << r.out;
      EXPECT_NE(r.out.find("the run is not committed (no results folder full)"), std::string::npos) << r.out;
      EXPECT_EQ(r.out.find("HDF5-DIAG"), std::string::npos) << r.out;
      EXPECT_LT(std::count(r.out.begin(), r.out.end(), '\n'), 3) << r.out;
      EXPECT_TRUE(fs::is_empty(dir)) << ex << ": " << entriesWith(dir, "").size() << " entries left";
    }
  }
  fs::remove_all(dir);
}

TEST(Cli, ATrailingSlashInOutNamesTheSameFolder) {
  const fs::path out = scratch("slash");
  auto r = runCli("run " + example("gelatin_18G_3mms.yaml") + " --quiet --out " + out.string() + "//");
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_TRUE(fs::exists(out / "summary.json"));
  EXPECT_TRUE(entriesWith(out.parent_path(), ".partial-").empty());
  auto dot = runCli("run " + example("gelatin_18G_3mms.yaml") + " --quiet --out " + out.string() + "/. --overwrite");
  EXPECT_EQ(dot.code, 0) << dot.out;
  auto none = runCli("run " + example("gelatin_18G_3mms.yaml") + " --quiet --out ..");
  EXPECT_EQ(none.code, 2) << none.out;
  EXPECT_NE(none.out.find("--out: names no results folder"), std::string::npos) << none.out;
}

TEST(Cli, OverwriteDeletesOnlyANeedlesimCheckpointFolder) {
  const fs::path out = scratch("ck_user");
  const fs::path ck = out.string() + ".checkpoint";
  fs::remove_all(ck);
  fs::create_directories(ck);
  std::ofstream(ck / "notes.txt") << "mine";
  auto r = runCli("run " + example("mpm/quick_needle_block.yaml") + " --quiet --overwrite --out " + out.string());
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find("a folder holding notes.txt, not a needlesim checkpoint folder"), std::string::npos) << r.out;
  EXPECT_TRUE(fs::exists(ck / "notes.txt"));
  EXPECT_FALSE(fs::exists(out));
  fs::remove_all(ck);
}

// The output path is checked before the run: a name too long for the file
// system, a path too long, a folder that cannot be created or written.
TEST(Cli, AnUnwritableOrTooLongOutputIsRefusedBeforeTheRun) {
  const std::string run = "run " + example("mpm/quick_needle_block.yaml") + " --quiet --out ";
  auto longName = runCli(run + scratch("n").parent_path().string() + "/" + std::string(250, 'n'));
  EXPECT_EQ(longName.code, 2) << longName.out;
  EXPECT_NE(longName.out.find("--out: its folder name has 250 characters, too long"), std::string::npos) << longName.out;
  EXPECT_NE(longName.out.find("allowed: a name of at most 230 characters"), std::string::npos) << longName.out;
  std::string deep = scratch("deep").string();
  while (deep.size() < 4200) deep += "/" + std::string(200, 'd');
  auto longPath = runCli(run + deep);
  EXPECT_EQ(longPath.code, 2) << longPath.out;
  EXPECT_NE(longPath.out.find("is too long for the file system"), std::string::npos) << longPath.out.substr(0, 300);
  EXPECT_FALSE(fs::exists(scratch("deep")));
  const fs::path file = scratch("a_file");
  std::ofstream(file) << "x";
  auto underFile = runCli(run + (file / "res").string());
  EXPECT_EQ(underFile.code, 2) << underFile.out;
  EXPECT_NE(underFile.out.find("--out: its folder " + file.string() + " cannot be created"), std::string::npos)
      << underFile.out;
  auto proc = runCli(run + "/proc/needlesim_results");  // a folder nobody can write, root included
  EXPECT_EQ(proc.code, 2) << proc.out;
  EXPECT_NE(proc.out.find("--out: its folder /proc is not writable"), std::string::npos) << proc.out;
  EXPECT_EQ(proc.out.find("needlesim: running"), std::string::npos);  // refused before the run (and --quiet)
}

// Ctrl-C stops a run cleanly: a final checkpoint (mpm), no staging folder, no
// results folder, exit code 130, and --resume finishes the run.
TEST(Cli, CtrlCStopsARunWithAFinalCheckpointAndResumeFinishesIt) {
  const fs::path dir = scratch("ctrl_c");
  editedExample("mpm/quick_needle_block.yaml", "speed: 6 mm/s", "speed: 0.25 mm/s", dir / "slow.yaml");
  const fs::path out = dir / "res", ck = dir / "res.checkpoint", log = dir.parent_path() / "ctrl_c.log";
  const pid_t pid = startCli("run " + (dir / "slow.yaml").string() + " --out " + out.string(), log);
  ASSERT_TRUE(appears(dir / (".res.partial-" + std::to_string(pid)), 30));
  usleep(300000);
  kill(pid, SIGINT);
  EXPECT_EQ(waitFor(pid, 60), 130) << text(log);
  const std::string said = text(log);
  EXPECT_NE(said.find("interrupted by SIGINT (Ctrl-C)"), std::string::npos) << said;
  EXPECT_NE(said.find("nothing was written to " + out.string()), std::string::npos) << said;
  EXPECT_NE(said.find("the checkpoint " + ck.string() + " is kept"), std::string::npos) << said;
  EXPECT_NE(said.find("--resume"), std::string::npos) << said;
  EXPECT_TRUE(fs::exists(ck / "state.bin"));
  EXPECT_FALSE(fs::exists(out));
  EXPECT_TRUE(entriesWith(dir, ".partial-").empty());
  auto resumed = runCli("run " + (dir / "slow.yaml").string() + " --quiet --resume --out " + out.string());
  EXPECT_EQ(resumed.code, 0) << resumed.out;
  EXPECT_EQ(nlohmann::json::parse(std::ifstream(out / "summary.json"))["status"], "complete");
  fs::remove_all(dir);
}

// SIGTERM stops an engine without checkpoints: exit code 143, nothing left behind.
TEST(Cli, SigtermStopsARunAndLeavesNothingBehind) {
  const fs::path dir = scratch("sigterm");
  fs::create_directories(dir);
  const fs::path out = dir / "res", log = dir.parent_path() / "sigterm.log";
  const pid_t pid = startCli("run " + example("realtime2d/layered_target.yaml") + " --out " + out.string(), log);
  ASSERT_TRUE(appears(dir / (".res.partial-" + std::to_string(pid)), 30));
  kill(pid, SIGTERM);
  EXPECT_EQ(waitFor(pid, 60), 143) << text(log);
  EXPECT_NE(text(log).find("interrupted by SIGTERM"), std::string::npos) << text(log);
  EXPECT_TRUE(fs::is_empty(dir)) << entriesWith(dir, "").size() << " entries left";
  fs::remove_all(dir);
}

// A run killed with SIGKILL leaves its staging folder; the next run into the
// same folder removes those of dead processes and keeps a live one's.
TEST(Cli, ARunRemovesTheStagingFoldersOfKilledRunsOnly) {
  const fs::path dir = scratch("killed");
  fs::create_directories(dir);
  const pid_t child = fork();
  if (child == 0) _exit(0);
  waitpid(child, nullptr, 0);
  const fs::path dead = dir / (".old.partial-" + std::to_string(child));
  const fs::path live = dir / (".other.partial-" + std::to_string(::getpid()));
  fs::create_directories(dead);
  fs::create_directories(live);
  std::ofstream(dir / "thesis.tex") << "mine";
  auto r = runCli("run " + example("gelatin_18G_3mms.yaml") + " --quiet --out " + (dir / "res").string());
  EXPECT_EQ(r.code, 0) << r.out;
  EXPECT_FALSE(fs::exists(dead));
  EXPECT_TRUE(fs::exists(live));
  EXPECT_TRUE(fs::exists(dir / "thesis.tex"));
  fs::remove_all(dir);
}

// A warning reaches the terminal as it is raised, summary.json's "warnings"
// and a box at the top of the report; --quiet keeps the terminal quiet.
TEST(Cli, WarningsReachTheTerminalTheSummaryAndTheReport) {
  const fs::path out = scratch("warned");
  auto r = runCli("run " + example("explicit/target_inclusion_2d.yaml") + " --out " + out.string());
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("warning: Kinetic energy exceeded 10 %"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("results: " + out.string() + "/"), std::string::npos) << r.out;  // the closing line stays
  const auto s = nlohmann::json::parse(std::ifstream(out / "summary.json"));
  ASSERT_FALSE(s["warnings"].empty());
  EXPECT_NE(s["warnings"][0].get<std::string>().find("not quasi-static"), std::string::npos);
  EXPECT_NE(text(out / "report.html").find("<div class=\"warnings\""), std::string::npos);
  auto quiet = runCli("run " + example("explicit/target_inclusion_2d.yaml") + " --quiet --overwrite --out " + out.string());
  EXPECT_EQ(quiet.code, 0) << quiet.out;
  EXPECT_EQ(quiet.out, "");
}

// `check` runs each engine's own refusals (not only the scenario reader's), so it
// passes nothing that `run` refuses: the energy model is planar and takes only
// 180-degree bevel flips.
TEST(Cli, CheckRefusesWhatTheEngineRefusesAtRun) {
  fs::path dir = scratch("engine_refusal");
  fs::create_directories(dir);
  std::ifstream in(example("steering/flip_s_curve.yaml"));
  std::string yaml((std::istreambuf_iterator<char>(in)), {});
  for (auto [from, to] : {std::pair<std::string, std::string>{"by: 180 deg", "by: 90 deg"},
                          {"engine: kinematic", "engine: energy"}}) {
    const auto pos = yaml.find(from);
    ASSERT_NE(pos, std::string::npos) << from;
    yaml.replace(pos, from.size(), to);
  }
  std::ofstream(dir / "quarter_turn.yaml") << yaml;
  for (const std::string& cmd : {std::string("check "), "run --quiet --out " + (dir / "out").string() + " "}) {
    auto r = runCli(cmd + (dir / "quarter_turn.yaml").string());
    EXPECT_EQ(r.code, 2) << cmd << r.out;
    EXPECT_NE(r.out.find("insertion.profile"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("180-degree flips"), std::string::npos) << r.out;
  }
  EXPECT_FALSE(fs::exists(dir / "out"));
}

// Ctrl-C during a sweep stops the running case cleanly (nothing half-written),
// keeps the finished cases, exits 130 and says how to continue; --resume runs
// only what is missing.
TEST(Cli, CtrlCStopsASweepAndResumeRunsWhatIsMissing) {
  const fs::path dir = scratch("sweep_sigint");
  fs::create_directories(dir);
  std::ofstream(dir / "study.yaml") << "scenario: " << example("realtime2d/layered_target.yaml")
                                    << "\nname: s\nmethod: list\nparallel: 1\ndirectory: " << (dir / "s").string()
                                    << "\nvary:\n  - field: needle.length\n    values: [100 mm, 101 mm]\n";
  const fs::path log = dir.parent_path() / "sweep_sigint.log";
  const pid_t pid = startCli("sweep " + (dir / "study.yaml").string(), log);
  ASSERT_TRUE(appears(dir / "s" / "cases", 30));
  usleep(300000);  // inside the first case (about 2 s)
  kill(pid, SIGINT);
  EXPECT_EQ(waitFor(pid, 60), 130) << text(log);
  EXPECT_NE(text(log).find("interrupted by SIGINT"), std::string::npos) << text(log);
  EXPECT_NE(text(log).find("--resume"), std::string::npos) << text(log);
  EXPECT_FALSE(fs::exists(dir / "s" / "cases" / "case_0001.error.txt"));  // an interruption is not a failure
  EXPECT_TRUE(entriesWith(dir / "s" / "cases", ".partial-").empty());
  auto r = runCli("sweep " + (dir / "study.yaml").string() + " --resume --quiet");
  EXPECT_EQ(r.code, 0) << r.out;
  EXPECT_TRUE(fs::exists(dir / "s" / "cases" / "case_0002" / "summary.json"));
  fs::remove_all(dir);
}

// Bad arguments are bad input (exit 2, with what is wrong); --help and --version succeed.
TEST(Cli, BadArgumentsExitWith2AndSayWhatIsWrong) {
  auto unknown = runCli("run --no-such-flag");
  EXPECT_EQ(unknown.code, 2) << unknown.out;
  EXPECT_NE(unknown.out.find("--no-such-flag"), std::string::npos) << unknown.out;
  auto missing = runCli("check");
  EXPECT_EQ(missing.code, 2) << missing.out;
  EXPECT_NE(missing.out.find("file is required"), std::string::npos) << missing.out;
  EXPECT_EQ(runCli("--help").code, 0);
  EXPECT_EQ(runCli("--version").code, 0);
}

// A cohesive law that has no bilinear triangle (onset beyond the final separation) is bad
// input, refused by check as by run with the line of the cohesive section.
TEST(Cli, ACohesiveLawWithoutABilinearTriangleIsRefusedWithItsLine) {
  fs::path dir = scratch("cohesive_law");
  fs::create_directories(dir);
  std::ifstream in(example("cohesive/seed004_table1_2d.yaml"));
  std::string yaml((std::istreambuf_iterator<char>(in)), {});
  const std::string at = "    cohesive:\n";
  const auto pos = yaml.find(at);
  ASSERT_NE(pos, std::string::npos);
  yaml.insert(pos + at.size(), "      stiffness: 1 Pa/m\n");
  std::ofstream(dir / "soft_law.yaml") << yaml;
  // the line of the inserted stiffness: the one after `cohesive:`
  const auto line = std::count(yaml.begin(), yaml.begin() + static_cast<std::ptrdiff_t>(pos), '\n') + 2;
  const std::string where = "soft_law.yaml:" + std::to_string(line) + ":";
  for (const std::string& cmd : {std::string("check "), "run --quiet --out " + (dir / "out").string() + " "}) {
    auto r = runCli(cmd + (dir / "soft_law.yaml").string());
    EXPECT_EQ(r.code, 2) << cmd << r.out;
    EXPECT_NE(r.out.find(where), std::string::npos) << where << "\n" << r.out;
    EXPECT_NE(r.out.find("model.explicit.cohesive"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("no bilinear law exists"), std::string::npos) << r.out;
  }
  EXPECT_FALSE(fs::exists(dir / "out"));
}
