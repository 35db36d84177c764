// A study folder holds the user's files safely: --overwrite deletes only what
// needlesim wrote, --resume reruns a case whose summary cannot be read, and one
// needlesim at a time writes a folder (the lock beside it).
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <csignal>
#include <filesystem>
#include <fstream>
#include <string>
#include <sys/wait.h>
#include <unistd.h>

#include "../app/cli_run.hpp"
#include "needlesim/core/error.hpp"
#include "needlesim/io/folder_lock.hpp"
#include "needlesim/study/study.hpp"

using namespace needlesim;
using namespace needlesim::study;
namespace fs = std::filesystem;

namespace {

fs::path scratch(const std::string& name) {
  fs::path d = fs::temp_directory_path() / ("needlesim_safety_" + std::to_string(::getpid())) / name;
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

std::string text(const fs::path& p) { return std::string((std::istreambuf_iterator<char>(std::ifstream(p).rdbuf())), {}); }

// Two lumped cases (milliseconds each) on the default example.
fs::path quickStudy(const fs::path& dir) {
  std::ofstream(dir / "study.yaml") << "scenario: " << NEEDLESIM_SOURCE_DIR << "/examples/gelatin_18G_3mms.yaml\n"
                                    << "name: quick\nmethod: list\ndirectory: " << (dir / "s").string()
                                    << "\nvary:\n  - {field: tissue.friction.C_p, values: [2 N/m, 3 N/m]}\n";
  return dir / "study.yaml";
}

SweepOptions quiet() {
  SweepOptions o;
  o.progress = false;
  return o;
}

bool mentions(const std::vector<std::string>& notes, const std::string& part) {
  for (const auto& n : notes)
    if (n.find(part) != std::string::npos) return true;
  return false;
}

}  // namespace

// --overwrite deletes the files a case's summary lists; a file the user put in
// the case folder survives (the folder is kept aside, unchanged) and is named.
TEST(StudyFolderSafety, OverwriteKeepsAFileTheUserPutInACaseFolder) {
  const fs::path dir = scratch("users_file");
  const StudySpec spec = readStudyFile(quickStudy(dir));
  runSweep(spec, quiet());
  const fs::path mine = dir / "s" / "cases" / "case_0001" / "my_notes.txt";
  std::ofstream(mine) << "keep me\n";
  SweepOptions opt = quiet();
  opt.overwrite = true;
  const SweepReport rep = runSweep(spec, opt);
  EXPECT_EQ(rep.ran, 2);
  const fs::path kept = dir / "s" / "cases" / "case_0001.kept-1";
  EXPECT_EQ(text(kept / "my_notes.txt"), "keep me\n");
  EXPECT_FALSE(fs::exists(kept / "summary.json"));  // needlesim's own files were deleted
  EXPECT_TRUE(mentions(rep.notes, "cases/case_0001.kept-1")) << (rep.notes.empty() ? "" : rep.notes[0]);
  EXPECT_TRUE(mentions(rep.notes, "my_notes.txt"));
  EXPECT_TRUE(fs::exists(dir / "s" / "cases" / "case_0001" / "summary.json"));  // the case ran again
  // A second --overwrite leaves the kept folder alone.
  const SweepReport again = runSweep(spec, opt);
  EXPECT_EQ(text(kept / "my_notes.txt"), "keep me\n");
  EXPECT_TRUE(mentions(again.notes, "case_0001.kept-1 is left as it is"));
  fs::remove_all(dir);
}

// --resume over a case whose summary.json was cut short: the case runs again
// (said on the terminal), nothing is deleted, and no JSON error reaches the user.
TEST(StudyFolderSafety, ResumeRerunsACaseWhoseSummaryIsCutShort) {
  if (!fs::exists(NEEDLESIM_BINARY)) GTEST_SKIP() << "needlesim binary not built";
  const fs::path dir = scratch("truncated");
  const std::string sweep = std::string(NEEDLESIM_BINARY) + " sweep " + quickStudy(dir).string();
  ASSERT_EQ(test::runShell(sweep + " -q").code, 0);
  const fs::path summary = dir / "s" / "cases" / "case_0002" / "summary.json";
  const std::string whole = text(summary);
  std::ofstream(summary, std::ios::trunc) << whole.substr(0, whole.size() / 2);
  const auto r = test::runShell(sweep + " --resume");
  EXPECT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("cases/case_0002: its summary.json cannot be read"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("2 cases, 1 run now, 1 reused"), std::string::npos) << r.out;
  EXPECT_EQ(nlohmann::json::parse(std::ifstream(summary))["status"], "complete");
  EXPECT_EQ(text(dir / "s" / "cases" / "case_0002.kept-1" / "summary.json"), whole.substr(0, whole.size() / 2));
  fs::remove_all(dir);
}

// A folder another needlesim writes is refused, for sweep and run, before anything is touched.
TEST(StudyFolderSafety, AFolderInUseIsRefusedWithTheLock) {
  if (!fs::exists(NEEDLESIM_BINARY)) GTEST_SKIP() << "needlesim binary not built";
  const fs::path dir = scratch("held");
  const std::string study = quickStudy(dir).string();
  ASSERT_EQ(test::runShell(std::string(NEEDLESIM_BINARY) + " sweep -q " + study).code, 0);
  const std::string before = text(dir / "s" / "study.csv");
  {
    const io::FolderLock held(dir / "s", "--out", commandLine());
    const auto sweep = test::runShell(std::string(NEEDLESIM_BINARY) + " sweep -q --overwrite " + study);
    EXPECT_EQ(sweep.code, 2) << sweep.out;
    EXPECT_NE(sweep.out.find("directory: " + (dir / "s").string() + " is being written by another needlesim"),
              std::string::npos)
        << sweep.out;
    const auto run = test::runShell(std::string(NEEDLESIM_BINARY) + " run -q " + NEEDLESIM_SOURCE_DIR +
                                    "/examples/gelatin_18G_3mms.yaml --out " + (dir / "r").string());
    EXPECT_EQ(run.code, 0) << run.out;  // another folder: free
    const io::FolderLock heldRun(dir / "r2", "--out", commandLine());
    const auto blocked = test::runShell(std::string(NEEDLESIM_BINARY) + " run -q " + NEEDLESIM_SOURCE_DIR +
                                        "/examples/gelatin_18G_3mms.yaml --out " + (dir / "r2").string());
    EXPECT_EQ(blocked.code, 2) << blocked.out;
    EXPECT_NE(blocked.out.find("--out: " + (dir / "r2").string() + " is being written by another needlesim"),
              std::string::npos)
        << blocked.out;
    EXPECT_FALSE(fs::exists(dir / "r2"));
  }
  EXPECT_EQ(text(dir / "s" / "study.csv"), before);
  EXPECT_FALSE(fs::exists(io::FolderLock::lockFileOf(dir / "s")));  // the last holder removes it
  fs::remove_all(dir);
}

// Two sweeps started into one folder at once: the second is refused with the
// lock's message, the first completes every case.
TEST(StudyFolderSafety, TwoConcurrentSweepsIntoOneFolder) {
  if (!fs::exists(NEEDLESIM_BINARY)) GTEST_SKIP() << "needlesim binary not built";
  const fs::path dir = scratch("concurrent");
  std::ofstream(dir / "study.yaml") << "scenario: " << NEEDLESIM_SOURCE_DIR << "/examples/realtime2d/layered_target.yaml"
                                    << "\nname: two\nmethod: list\nparallel: 1\ndirectory: " << (dir / "s").string()
                                    << "\nvary:\n  - field: needle.length\n    values: [100 mm, 101 mm]\n";
  const std::string sweep = std::string(NEEDLESIM_BINARY) + " sweep -q --overwrite " + (dir / "study.yaml").string();
  const fs::path log = dir / "first.log";
  const pid_t first = fork();
  if (first == 0) {
    const std::string cmd = "exec " + sweep + " > '" + log.string() + "' 2>&1";
    execl("/bin/sh", "sh", "-c", cmd.c_str(), static_cast<char*>(nullptr));
    _exit(127);
  }
  const fs::path lock = io::FolderLock::lockFileOf(dir / "s");
  for (int i = 0; i < 600 && !fs::exists(dir / "s" / "cases"); ++i) usleep(50000);
  ASSERT_TRUE(fs::exists(lock));
  const auto second = test::runShell(sweep);
  EXPECT_EQ(second.code, 2) << second.out;
  EXPECT_NE(second.out.find("is being written by another needlesim (process " + std::to_string(first) + ")"),
            std::string::npos)
      << second.out;
  int status = 0;
  waitpid(first, &status, 0);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << text(log);
  for (const char* c : {"case_0001", "case_0002"})
    EXPECT_EQ(nlohmann::json::parse(std::ifstream(dir / "s" / "cases" / c / "summary.json"))["status"], "complete");
  EXPECT_TRUE(fs::exists(dir / "s" / "study.csv"));
  EXPECT_FALSE(fs::exists(dir / "s" / "cases" / "case_0001.error.txt"));
  fs::remove_all(dir);
}
