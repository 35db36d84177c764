// `needlesim fit` end to end through the binary: exit codes and files.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace fs = std::filesystem;

namespace {
struct CliRun {
  int code;
  std::string out;
};
CliRun run(const std::string& args) {
  // one log per test process: ctest runs the tests of this file at the same time
  fs::path log = fs::temp_directory_path() / ("needlesim_fit_cli_" + std::to_string(::getpid()) + ".log");
  std::string cmd = std::string("\"") + NEEDLESIM_BINARY + "\" fit " + args + " > \"" + log.string() + "\" 2>&1";
  int status = std::system(cmd.c_str());
  std::stringstream ss;
  ss << std::ifstream(log).rdbuf();
  fs::remove(log);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, ss.str()};
}
std::string ex(const std::string& f) { return std::string(NEEDLESIM_SOURCE_DIR) + "/examples/data/" + f; }
}  // namespace

TEST(FitCli, WritesJsonAndReportAndNeverOverwrites) {
  if (!fs::exists(NEEDLESIM_BINARY)) GTEST_SKIP() << "needlesim binary not built";
  fs::path out = fs::temp_directory_path() / "needlesim_fit_cli_out";
  fs::remove_all(out);
  CliRun r = run("\"" + ex("plastisol_compression.csv") + "\" --law neo-hookean --out \"" + out.string() + "\"");
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("C10"), std::string::npos);
  EXPECT_TRUE(fs::exists(out / "fit.json"));
  EXPECT_TRUE(fs::exists(out / "report.html"));
  CliRun again = run("\"" + ex("plastisol_compression.csv") + "\" --law neo-hookean --out \"" + out.string() + "\"");
  EXPECT_EQ(again.code, 2) << again.out;
  EXPECT_NE(again.out.find("already exists"), std::string::npos);
  CliRun ow = run("\"" + ex("plastisol_compression.csv") + "\" --law linear --overwrite --out \"" + out.string() + "\"");
  EXPECT_EQ(ow.code, 0) << ow.out;
  fs::remove_all(out);
}

TEST(FitCli, BadDataExitsWithCode2AndNamesFileAndLine) {
  if (!fs::exists(NEEDLESIM_BINARY)) GTEST_SKIP() << "needlesim binary not built";
  fs::path f = fs::temp_directory_path() / "needlesim_bad.csv";
  std::ofstream(f) << "strain [1], stress [kPa]\n0.1, 1\n0.2, oops\n";
  CliRun r = run("\"" + f.string() + "\" --law fung --out \"" + (fs::temp_directory_path() / "nf_bad.fit").string() + "\"");
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find(f.string() + ":3:"), std::string::npos) << r.out;
  CliRun u = run("\"" + f.string() + "\" --law elastic");
  EXPECT_EQ(u.code, 2) << u.out;
  fs::remove(f);
}

TEST(FitCli, MissingLawExitsWithCode2AndListsTheLaws) {
  if (!fs::exists(NEEDLESIM_BINARY)) GTEST_SKIP() << "needlesim binary not built";
  CliRun r = run("\"" + ex("plastisol_compression.csv") + "\"");
  EXPECT_EQ(r.code, 2) << r.out;
  for (const char* w : {"--law", "is missing", "neo-hookean", "auto", "prony", "friction", "stiffness"})
    EXPECT_NE(r.out.find(w), std::string::npos) << "missing '" << w << "' in: " << r.out;
  CliRun noData = run("--law fung");
  EXPECT_EQ(noData.code, 2) << noData.out;
  EXPECT_NE(noData.out.find("no data file given"), std::string::npos) << noData.out;
}
