// Where `needlesim fit` writes: results/<name made from all its inputs>, or
// --out; staged and moved into place like a run's folder; a user's folder is
// never replaced.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <unistd.h>

#include "../app/cli_run.hpp"
#include "needlesim/core/error.hpp"
#include "needlesim/fit/fit_command.hpp"

using namespace needlesim;
using namespace needlesim::fit;
namespace fs = std::filesystem;

namespace {

std::string ex(const std::string& f) { return std::string(NEEDLESIM_SOURCE_DIR) + "/examples/data/" + f; }

fs::path scratch(const std::string& name) {
  fs::path d = fs::temp_directory_path() / ("needlesim_fit_folder_" + std::to_string(::getpid())) / name;
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

// Runs the test body in `dir` and goes back to the folder it started in.
class InFolder {
 public:
  explicit InFolder(const fs::path& dir) : before_(fs::current_path()) { fs::current_path(dir); }
  ~InFolder() { fs::current_path(before_); }

 private:
  fs::path before_;
};

std::string text(const fs::path& p) {
  std::stringstream ss;
  ss << std::ifstream(p).rdbuf();
  return ss.str();
}

FitRequest neoHookean() {
  FitRequest rq;
  rq.data = {ex("plastisol_compression.csv")};
  rq.law = "neo-hookean";
  return rq;
}

// needlesim fit ARGS run in `dir`.
test::CliResult fitIn(const fs::path& dir, const std::string& args) {
  return test::runShell("cd '" + dir.string() + "' && " + NEEDLESIM_BINARY + " fit " + args);
}

}  // namespace

TEST(FitFolderName, NamesEveryDataFileInOrderAndTheAnalysis) {
  EXPECT_EQ(fitResultsName({"examples/data/plastisol_compression.csv"}, "auto"), "fit_plastisol_compression_auto");
  EXPECT_EQ(fitResultsName({"d/gelatin_2.5mms.csv", "d/gelatin_3.33mms.csv", "gelatin_5mms.csv"}, "friction"),
            "fit_gelatin_2.5mms+gelatin_3.33mms+gelatin_5mms_friction");
  EXPECT_EQ(fitResultsName({"b.csv", "a.csv"}, "puncture"), "fit_b+a_puncture");  // the order given
  EXPECT_EQ(fitResultsName({"lab run 3 (ok)+x.csv"}, "fung"), "fit_lab_run_3__ok__x_fung");
  EXPECT_EQ(fitResultsName({"Gewebe_\xc3\xbc\x62\x65r.csv"}, "linear"), "fit_Gewebe_\xc3\xbc\x62\x65r_linear");  // UTF-8 stays
}

TEST(FitFolderName, ManyFilesGiveABoundedNameThatStillTellsThemApart) {
  std::vector<fs::path> many;
  for (int i = 0; i < 12; ++i) many.push_back("logs/insertion_run_" + std::to_string(10 + i) + ".csv");
  const std::string name = fitResultsName(many, "toughness");
  EXPECT_EQ(name, "fit_insertion_run_10+insertion_run_11+insertion_run_12+9_more-484aab9b_toughness");  // docs/fitting.md
  EXPECT_LE(name.size(), 4 + kMaxFitNameStems + 20 + 1 + std::string("toughness").size()) << name;
  EXPECT_EQ(name, fitResultsName(many, "toughness"));  // stable
  auto other = many;
  other.back() = "logs/insertion_run_99.csv";  // differs only in a file the name leaves out
  EXPECT_NE(fitResultsName(other, "toughness"), name);
  EXPECT_EQ(fitResultsName(other, "toughness").size(), name.size());
  // One stem longer than the bound is cut (never inside a UTF-8 character) and hashed.
  const std::string longStem(kMaxFitNameStems - 1, 'a');
  const std::string cut = fitResultsName({longStem + "\xc3\xbc" + "tail.csv"}, "auto");
  EXPECT_EQ(cut.rfind("fit_" + longStem + "-", 0), 0u) << cut;
  EXPECT_NE(fitResultsName({longStem + "\xc3\xbc" + "tail2.csv"}, "auto"), cut);
}

TEST(FitFolder, DefaultsToResultsNamedAfterTheInputsAndNeverSharesAFolder) {
  const fs::path dir = scratch("default");
  InFolder in(dir);
  const FitOutcome first = runFit(neoHookean());
  EXPECT_EQ(first.outDir, fs::path("results/fit_plastisol_compression_neo-hookean"));
  const auto j = nlohmann::json::parse(text(first.outDir / "fit.json"));
  EXPECT_EQ(j["status"], "complete");
  EXPECT_TRUE(j["needlesim"].contains("version"));
  EXPECT_TRUE(fs::exists(first.outDir / "report.html"));
  // The same inputs again: a new folder beside it, like `needlesim run`.
  EXPECT_EQ(runFit(neoHookean()).outDir, fs::path("results/fit_plastisol_compression_neo-hookean-2"));
  // Other inputs: another name.
  FitRequest friction;
  friction.data = {ex("gelatin_2.5mms.csv"), ex("gelatin_10mms.csv")};
  friction.law = "friction";
  friction.thickness = 55e-3;
  EXPECT_EQ(runFit(friction).outDir, fs::path("results/fit_gelatin_2.5mms+gelatin_10mms_friction"));
  std::swap(friction.data[0], friction.data[1]);
  EXPECT_EQ(runFit(friction).outDir, fs::path("results/fit_gelatin_10mms+gelatin_2.5mms_friction"));
  for (const auto& e : fs::directory_iterator("results"))  // nothing staged is left behind
    EXPECT_NE(e.path().filename().string()[0], '.') << e.path();
}

TEST(FitFolder, OutIsRefusedWhenItExistsAndOverwriteReplacesOnlyAResultsFolder) {
  const fs::path dir = scratch("out");
  FitRequest rq = neoHookean();
  rq.out = dir / "mine";
  EXPECT_EQ(runFit(rq).outDir, dir / "mine");
  EXPECT_THROW(runFit(rq), InputError);  // exists
  rq.overwrite = true;
  rq.law = "linear";
  runFit(rq);
  EXPECT_EQ(nlohmann::json::parse(text(dir / "mine" / "fit.json"))["analysis"], "linear");

  fs::create_directories(dir / "thesis");
  std::ofstream(dir / "thesis" / "chapter1.tex") << "keep me\n";
  rq.out = dir / "thesis";
  try {
    runFit(rq);
    ADD_FAILURE() << "a user's folder was replaced";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("holding chapter1.tex, not a needlesim results folder"), std::string::npos)
        << e.what();
  }
  EXPECT_EQ(text(dir / "thesis" / "chapter1.tex"), "keep me\n");
  EXPECT_FALSE(fs::exists(dir / "thesis" / "fit.json"));
}

TEST(FitFolder, TheTerminalSaysWhereItWrote) {
  if (!fs::exists(NEEDLESIM_BINARY)) GTEST_SKIP() << "needlesim binary not built";
  const fs::path dir = scratch("cli");
  auto r = fitIn(dir, "'" + ex("gelatin_2.5mms.csv") + "' '" + ex("gelatin_5mms.csv") + "' --law friction --thickness '55 mm'");
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("results: results/fit_gelatin_2.5mms+gelatin_5mms_friction/ (fit.json, report.html)"),
            std::string::npos)
      << r.out;
  EXPECT_TRUE(fs::exists(dir / "results" / "fit_gelatin_2.5mms+gelatin_5mms_friction" / "fit.json"));
  fs::create_directories(dir / "notes");
  std::ofstream(dir / "notes" / "todo.txt") << "mine\n";
  auto refused = fitIn(dir, "'" + ex("plastisol_compression.csv") + "' --law auto --out notes --overwrite");
  EXPECT_EQ(refused.code, 2) << refused.out;
  EXPECT_NE(refused.out.find("--out"), std::string::npos) << refused.out;
  EXPECT_NE(refused.out.find("not a needlesim results folder"), std::string::npos) << refused.out;
  EXPECT_EQ(text(dir / "notes" / "todo.txt"), "mine\n");
  auto out = fitIn(dir, "'" + ex("plastisol_compression.csv") + "' --law auto -o fits/plastisol");
  EXPECT_EQ(out.code, 0) << out.out;
  EXPECT_NE(out.out.find("results: fits/plastisol/ (fit.json, report.html)"), std::string::npos) << out.out;
}
