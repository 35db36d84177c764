// Stop requests in every phase of a run (a long set-up included) and thread
// counts beyond the machine: what a user sees on the command line.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <chrono>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <string>
#include <sys/wait.h>
#include <thread>
#include <unistd.h>

#include "cli_run.hpp"

namespace fs = std::filesystem;

namespace {

fs::path scratchDir(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("needlesim_interrupt_" + std::to_string(::getpid())) / name;
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

std::string fileText(const fs::path& p) {
  return std::string((std::istreambuf_iterator<char>(std::ifstream(p).rdbuf())), {});
}

// `example` with each `from` replaced by its `to`, written to `file`.
void edited(const std::string& example, const std::vector<std::pair<std::string, std::string>>& edits,
            const fs::path& file) {
  std::string yaml = fileText(std::string(NEEDLESIM_SOURCE_DIR) + "/examples/" + example);
  for (const auto& [from, to] : edits) {
    const auto at = yaml.find(from);
    ASSERT_NE(at, std::string::npos) << from;
    yaml.replace(at, from.size(), to);
  }
  std::ofstream(file) << yaml;
}

// Exit code of `pid` and the seconds it took to end (killed after `limit` s: -1000).
std::pair<int, double> exitOf(pid_t pid, double limit) {
  const auto t0 = std::chrono::steady_clock::now();
  int status = 0;
  for (;;) {
    if (waitpid(pid, &status, WNOHANG) == pid) break;
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (s > limit) {
      kill(pid, SIGKILL);
      waitpid(pid, &status, 0);
      return {-1000, s};
    }
    usleep(20000);
  }
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -WTERMSIG(status), s};
}

// Waits until the run's log shows its estimate (printed once the stop handlers are in place and
// before the engine's set-up), so that a signal sent after it lands in the set-up however slowly
// the loaded machine started the program; false after `limit` s.
bool estimateShown(const fs::path& log, double limit) {
  const auto t0 = std::chrono::steady_clock::now();
  while (fileText(log).find("estimate: ") == std::string::npos) {
    if (std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() > limit) return false;
    usleep(20000);
  }
  return true;
}

}  // namespace

// A realtime3d block of 50,225 nodes takes 15-35 s to set up (mesh, assembly,
// factorisation, Lanczos modes); Ctrl-C 2 s after its estimate (assembly) and SIGTERM 5 s after
// (a later phase, the factorisation on a fast machine) end it within a few
// seconds with the step loop's clean exit: code 130 / 143, nothing written, no
// staging folder or lock file left.
TEST(Interrupt, CtrlCDuringALongRealtime3dSetUpEndsTheRunAtOnce) {
  const fs::path dir = scratchDir("realtime3d_setup");
  edited("realtime3d/thesis_gelatin_18G_3mms.yaml",
         {{"nodes_lateral: 29", "nodes_lateral: 35"}, {"nodes_height: 21", "nodes_height: 35"}}, dir / "big.yaml");
  const fs::path out = dir / "res", log = dir.parent_path() / "realtime3d_setup.log";
  for (const auto& [signal, after] : {std::pair{SIGINT, 2}, std::pair{SIGTERM, 5}}) {
    const pid_t pid = needlesim::test::startCli("run " + (dir / "big.yaml").string() + " --out " + out.string(), log);
    EXPECT_TRUE(estimateShown(log, 60.0)) << fileText(log);
    std::this_thread::sleep_for(std::chrono::seconds(after));
    kill(pid, signal);
    const auto [code, seconds] = exitOf(pid, 60);
    const std::string said = fileText(log);
    EXPECT_EQ(code, 128 + signal) << said;
    EXPECT_LT(seconds, 3.0) << said;
    EXPECT_NE(said.find(signal == SIGINT ? "interrupted by SIGINT (Ctrl-C)" : "interrupted by SIGTERM"),
              std::string::npos)
        << said;
    EXPECT_NE(said.find("nothing was written to " + out.string()), std::string::npos) << said;
    EXPECT_FALSE(fs::exists(out));
    for (const auto& e : fs::directory_iterator(dir))
      EXPECT_EQ(e.path().filename().string().find(".res."), std::string::npos) << e.path();  // staging, lock
  }
  fs::remove_all(dir);
}

// The mpm set-up (filling 2.3 million material points, several seconds here) has no step loop:
// a stop request during it still ends the run within the same margin, nothing written.
TEST(Interrupt, CtrlCDuringALongMpmSetUpEndsTheRunAtOnce) {
  const fs::path dir = scratchDir("mpm_setup");
  edited("mpm/quick_needle_block.yaml", {{"grid_spacing: 1 mm", "grid_spacing: 0.1 mm"},
                                          {"particle_spacing: 0.5 mm", "particle_spacing: 0.05 mm"}},
         dir / "big.yaml");
  const fs::path out = dir / "res", log = dir.parent_path() / "mpm_setup.log";
  const pid_t pid = needlesim::test::startCli("run " + (dir / "big.yaml").string() + " --out " + out.string(), log);
  EXPECT_TRUE(estimateShown(log, 60.0)) << fileText(log);
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  kill(pid, SIGINT);
  const auto [code, seconds] = exitOf(pid, 120);
  const std::string said = fileText(log);
  EXPECT_EQ(code, 128 + SIGINT) << said;
  EXPECT_LT(seconds, 3.0) << said;
  EXPECT_NE(said.find("interrupted by SIGINT (Ctrl-C)"), std::string::npos) << said;
  EXPECT_FALSE(fs::exists(out));
  fs::remove_all(dir);
}

// model.mpm.threads beyond the machine's cores is capped with a warning (terminal and
// summary.json); 1024 threads under an 8 GB address-space limit no longer end the run.
TEST(Interrupt, ThreadsBeyondTheCoresAreCappedWithAWarning) {
  const fs::path dir = scratchDir("threads");
  edited("mpm/quick_needle_block.yaml", {{"grid_spacing: 1 mm", "grid_spacing: 1 mm\n    threads: 1024"}},
         dir / "threads.yaml");
  const fs::path out = dir / "res";
  const auto r = needlesim::test::runShell("ulimit -v 8000000; " + std::string(NEEDLESIM_BINARY) + " run " +
                                           (dir / "threads.yaml").string() + " --out " + out.string());
  ASSERT_EQ(r.code, 0) << r.out;
  const unsigned cores = std::max(1u, std::thread::hardware_concurrency());
  const std::string warning = "model.mpm.threads: 1024 is more than this machine's " + std::to_string(cores) +
                              " hardware threads; " + std::to_string(cores) + " are used";
  EXPECT_NE(r.out.find("warning: " + warning), std::string::npos) << r.out;
  const auto summary = nlohmann::json::parse(std::ifstream(out / "summary.json"));
  bool inSummary = false;
  for (const auto& w : summary["warnings"]) inSummary = inSummary || w.get<std::string>().find(warning) != std::string::npos;
  EXPECT_TRUE(inSummary) << summary["warnings"].dump();
  fs::remove_all(dir);
}
