// How a study shows its results: the varied parameters as inputs in the study
// file's order, constant outputs named once and left out of the report's
// table and plots (study.csv keeps them); and the study folder: --out,
// --resume, --overwrite, and a user's folder left alone.
#include <gtest/gtest.h>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <unistd.h>

#include "../app/cli_run.hpp"
#include "needlesim/core/error.hpp"
#include "needlesim/study/study.hpp"
#include "needlesim/study/study_report.hpp"

using namespace needlesim;
using namespace needlesim::study;
namespace fs = std::filesystem;

namespace {

fs::path scratch(const std::string& name) {
  fs::path d = fs::temp_directory_path() / ("needlesim_study_report_" + std::to_string(::getpid())) / name;
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

std::string text(const fs::path& p) {
  std::stringstream ss;
  ss << std::ifstream(p).rdbuf();
  return ss.str();
}

// Two cases of the seed 003 gelatin that change only the friction (b_p written
// before C_p): everything up to the puncture, and the punctures, are the same.
StudySpec frictionStudy(const fs::path& dir) {
  std::ofstream(dir / "study.yaml") << "scenario: " << NEEDLESIM_SOURCE_DIR << "/examples/gelatin_18G_3mms.yaml\n"
                                    << "name: friction_only\nmethod: list\ndirectory: " << (dir / "out").string()
                                    << "\nvary:\n"
                                       "  - {field: tissue.friction.b_p, values: [200 N s/m^2, 300 N s/m^2]}\n"
                                       "  - {field: tissue.friction.C_p, values: [2 N/m, 3 N/m]}\n";
  return readStudyFile(dir / "study.yaml");
}

SweepOptions quiet() {
  SweepOptions o;
  o.progress = false;
  return o;
}

// The text between `from` and the next `to` in `s` (empty if `from` is absent).
std::string between(const std::string& s, const std::string& from, const std::string& to) {
  const auto a = s.find(from);
  if (a == std::string::npos) return {};
  const auto b = s.find(to, a + from.size());
  return s.substr(a, b == std::string::npos ? std::string::npos : b - a);
}

}  // namespace

TEST(StudyReport, AnOutputIsConstantOnlyWhenEveryCompleteCaseHasTheSameValue) {
  EXPECT_TRUE(constantOverCases({1.0, 1.0, 1.0}));
  EXPECT_TRUE(constantOverCases({0.0, 0.0}));
  EXPECT_TRUE(constantOverCases({0.1, 0.1 * (1 + 1e-13)}));  // round-off
  EXPECT_FALSE(constantOverCases({0.1, 0.1 * (1 + 1e-9)}));  // a real, if small, change
  EXPECT_FALSE(constantOverCases({0.0, 1e-300}));
  EXPECT_FALSE(constantOverCases({2.0, NAN}));               // missing in one case
  EXPECT_FALSE(constantOverCases({3.0}));                    // one case says nothing
  EXPECT_FALSE(constantOverCases({}));
}

TEST(StudyReport, ConstantOutputsAreNamedOnceAndLeftOutOfTheTableAndPlots) {
  const fs::path dir = scratch("constant");
  const StudySpec spec = frictionStudy(dir);
  const SweepReport rep = runSweep(spec, quiet());
  ASSERT_TRUE(rep.failed.empty());

  // The terminal: inputs in the study file's order, varying outputs, one constant line.
  const std::string& t = rep.overview;
  const auto inputs = t.find("  inputs (varied):\n"), bp = t.find("tissue.friction.b_p  2 values: 200 N s/m^2, 300 N s/m^2"),
             cp = t.find("tissue.friction.C_p  2 values: 2 N/m, 3 N/m"), outputs = t.find("  outputs over the 2 complete cases");
  ASSERT_NE(inputs, std::string::npos) << t;
  EXPECT_LT(inputs, bp) << t;
  EXPECT_LT(bp, cp) << t;
  EXPECT_LT(cp, outputs) << t;
  const std::string constant = between(t, "  constant over all cases: ", "\n");
  EXPECT_NE(constant.find("punctures = 1"), std::string::npos) << t;
  EXPECT_NE(constant.find("puncture_1_depth = "), std::string::npos) << t;
  EXPECT_EQ(constant.find("exit_force"), std::string::npos) << t;  // it changes with the friction
  EXPECT_NE(between(t, "  outputs over", "  constant").find("exit_force"), std::string::npos) << t;
  EXPECT_EQ(between(t, "  outputs over", "  constant").find("punctures"), std::string::npos) << t;

  // report.html: inputs and outputs as separate column groups; the constants only in their line.
  const std::string html = text(dir / "out" / "report.html");
  const std::string table = between(html, "<table class=\"cases\">", "</table>");
  EXPECT_NE(table.find("<th colspan=\"2\" class=\"g1\">inputs (varied)</th><th colspan=\"3\" class=\"g0\">outputs</th>"),
            std::string::npos)
      << table;
  EXPECT_LT(table.find("<th>tissue.friction.b_p ["), table.find("<th>tissue.friction.C_p [")) << table;
  EXPECT_NE(table.find("<th>exit_force ["), std::string::npos) << table;
  for (const char* c : {"punctures", "puncture_1_depth", "puncture_1_force", "peak_force_depth"}) {
    EXPECT_EQ(table.find(c), std::string::npos) << c;
    EXPECT_EQ(html.find(std::string(c) + " against"), std::string::npos) << c;
  }
  EXPECT_NE(html.find("exit_force against tissue.friction.b_p"), std::string::npos);
  EXPECT_NE(html.find("<th>constant over all cases</th><td>"), std::string::npos);
  EXPECT_NE(between(html, "<th>constant over all cases</th>", "</tr>").find("punctures = 1"), std::string::npos);
  EXPECT_NE(html.find("<th>input (varied): tissue.friction.b_p</th><td>2 values: 200 N s/m^2, 300 N s/m^2</td>"),
            std::string::npos);

  // study.csv keeps every column, the inputs labelled as such; study.json names the roles.
  const std::string csv = text(dir / "out" / "study.csv");
  const std::string header = csv.substr(0, csv.find('\n'));
  EXPECT_EQ(header.rfind("case [1],complete [1],input: tissue.friction.b_p [N s/m^2],input: tissue.friction.C_p [N/m],", 0), 0u)
      << header;
  EXPECT_NE(header.find("punctures [1]"), std::string::npos) << header;
  const auto j = nlohmann::json::parse(text(dir / "out" / "study.json"));
  EXPECT_EQ(j["inputs"], nlohmann::json({"tissue.friction.b_p", "tissue.friction.C_p"}));
  EXPECT_EQ(j["constant_outputs"]["punctures"]["value"].get<double>(), 1.0);
  EXPECT_FALSE(j["constant_outputs"].contains("exit_force"));
  EXPECT_EQ(j["outputs"], nlohmann::json({"exit_force", "max_friction_force", "peak_force"}));
}

TEST(StudyFolder, OutOverridesTheDirectoryOfTheStudyFile) {
  const fs::path dir = scratch("out");
  StudySpec spec = frictionStudy(dir);
  SweepOptions opt = quiet();
  opt.out = dir / "chosen/";  // a trailing '/' names the same folder
  const SweepReport rep = runSweep(spec, opt);
  EXPECT_EQ(rep.folder, dir / "chosen");
  EXPECT_TRUE(fs::exists(dir / "chosen" / "study.csv"));
  EXPECT_TRUE(fs::exists(dir / "chosen" / "cases" / "case_0002" / "summary.json"));
  EXPECT_FALSE(fs::exists(dir / "out"));
}

TEST(StudyFolder, AnExistingStudyIsRefusedResumedOrReplaced) {
  const fs::path dir = scratch("again");
  StudySpec spec = frictionStudy(dir);
  SweepOptions opt = quiet();
  opt.out = dir / "s";
  runSweep(spec, opt);
  try {
    runSweep(spec, opt);
    ADD_FAILURE() << "a second run into the same folder was not refused";
  } catch (const InputError& e) {
    for (const char* w : {"--out", "already exists", "--resume", "--overwrite"})
      EXPECT_NE(std::string(e.what()).find(w), std::string::npos) << w << " in " << e.what();
  }
  opt.resume = true;
  SweepReport resumed = runSweep(spec, opt);
  EXPECT_EQ(resumed.reused, 2);
  EXPECT_EQ(resumed.ran, 0);
  // A case of an earlier, larger study is not part of the replaced one.
  fs::copy(dir / "s" / "cases" / "case_0002", dir / "s" / "cases" / "case_0007", fs::copy_options::recursive);
  opt.resume = false;
  opt.overwrite = true;
  SweepReport replaced = runSweep(spec, opt);
  EXPECT_EQ(replaced.ran, 2);
  EXPECT_EQ(replaced.reused, 0);
  EXPECT_FALSE(fs::exists(dir / "s" / "cases" / "case_0007"));
  opt.resume = true;  // with --overwrite: contradictory
  EXPECT_THROW(runSweep(spec, opt), InputError);
}

TEST(StudyFolder, AFolderOfTheUsersIsNeverWrittenToOrDeleted) {
  const fs::path dir = scratch("users");
  StudySpec spec = frictionStudy(dir);
  fs::create_directories(dir / "thesis");
  std::ofstream(dir / "thesis" / "chapter1.tex") << "keep me\n";
  for (int mode = 0; mode < 3; ++mode) {
    SweepOptions opt = quiet();
    opt.out = dir / "thesis";
    opt.resume = mode == 1;
    opt.overwrite = mode == 2;
    try {
      runSweep(spec, opt);
      ADD_FAILURE() << "mode " << mode << ": the user's folder was used";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("holding chapter1.tex, not a needlesim study folder"), std::string::npos)
          << e.what();
    }
    EXPECT_EQ(text(dir / "thesis" / "chapter1.tex"), "keep me\n");
    EXPECT_FALSE(fs::exists(dir / "thesis" / "cases"));
  }
  EXPECT_TRUE(isStudyFolder(dir / "empty_does_not_exist") == false);
  fs::create_directories(dir / "empty");
  EXPECT_TRUE(isStudyFolder(dir / "empty"));
  fs::create_directories(dir / "interrupted" / "cases" / "case_0001");
  std::ofstream(dir / "interrupted" / "cases" / "case_0002.error.txt") << "failed\n";
  fs::create_directories(dir / "interrupted" / "cases" / ".case_0003.partial-123");
  EXPECT_TRUE(isStudyFolder(dir / "interrupted"));
  std::ofstream(dir / "interrupted" / "cases" / "notes.txt") << "mine\n";
  EXPECT_FALSE(isStudyFolder(dir / "interrupted"));
}

TEST(StudyFolder, SweepOutOnTheCommandLine) {
  if (!fs::exists(NEEDLESIM_BINARY)) GTEST_SKIP() << "needlesim binary not built";
  const fs::path dir = scratch("cli");
  frictionStudy(dir);
  const std::string sweep = std::string(NEEDLESIM_BINARY) + " sweep " + (dir / "study.yaml").string();
  auto r = test::runShell(sweep + " --out " + (dir / "cli_out").string());
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("results in " + (dir / "cli_out").string() + "/ (study.csv, report.html)\n  inputs (varied):\n"),
            std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("  constant over all cases: "), std::string::npos) << r.out;
  EXPECT_FALSE(fs::exists(dir / "out"));  // the study file's directory is not used
  auto again = test::runShell(sweep + " -q --out " + (dir / "cli_out").string());
  EXPECT_EQ(again.code, 2) << again.out;
  EXPECT_NE(again.out.find("error: command line: --out: the study folder already exists"), std::string::npos)
      << again.out;
  auto replaced = test::runShell(sweep + " --overwrite --out " + (dir / "cli_out").string());
  EXPECT_EQ(replaced.code, 0) << replaced.out;
  EXPECT_NE(replaced.out.find("2 cases, 2 run now, 0 reused"), std::string::npos) << replaced.out;
  // Ranks of mpirun share the folder: none of them may delete it.
  auto ranks = test::runShell("OMPI_COMM_WORLD_SIZE=2 " + sweep + " --overwrite --out " + (dir / "cli_out").string());
  EXPECT_EQ(ranks.code, 2) << ranks.out;
  EXPECT_NE(ranks.out.find("--overwrite: cannot be used under mpirun"), std::string::npos) << ranks.out;
  EXPECT_TRUE(fs::exists(dir / "cli_out" / "study.csv"));
}

// Up to 8 values are listed as written; more numbers by their smallest and largest.
TEST(StudyReport, InputLinesListFewValuesAndTheRangeOfMany) {
  const fs::path dir = scratch("input_lines");
  std::ofstream(dir / "study.yaml") << "scenario: " << NEEDLESIM_SOURCE_DIR << "/examples/gelatin_18G_3mms.yaml\n"
                                    << "method: latin-hypercube\nsamples: 12\nseed: 7\nvary:\n"
                                       "  - {field: tissue.friction.C_p, min: 2 N/m, max: 4 N/m}\n";
  const StudySpec lhs = readStudyFile(dir / "study.yaml");
  std::ifstream in(lhs.scenario_file);
  const std::string base((std::istreambuf_iterator<char>(in)), {});
  const std::vector<Case> cases = expandCases(lhs, base);
  double lo = 1e9, hi = -1e9;
  for (const auto& c : cases) {
    lo = std::min(lo, c.values_si[0]);
    hi = std::max(hi, c.values_si[0]);
  }
  const StudyResults r{lhs, cases, io::Table({{"case", "1"}, {"complete", "1"}, {inputColumnName("tissue.friction.C_p"), "N/m"}})};
  EXPECT_EQ(inputLines(r), std::vector<std::string>{fmt::format("12 values: from {:.6g} N/m to {:.6g} N/m", lo, hi)});
  EXPECT_GT(lo, 2.0);
  EXPECT_LT(hi, 4.0);

  std::ofstream(dir / "grid.yaml") << "scenario: " << NEEDLESIM_SOURCE_DIR << "/examples/gelatin_18G_3mms.yaml\n"
                                   << "vary:\n  - {field: tissue.friction.C_p, values: [3 N/m, 3000 mN/m, 2 N/m]}\n";
  const StudySpec grid = readStudyFile(dir / "grid.yaml");
  const std::vector<Case> gridCases = expandCases(grid, base);
  const StudyResults g{grid, gridCases, io::Table({{"case", "1"}, {"complete", "1"}, {inputColumnName("tissue.friction.C_p"), "N/m"}})};
  EXPECT_EQ(inputLines(g), std::vector<std::string>{"3 values: 3 N/m, 3000 mN/m, 2 N/m"});
}

// Each column of the case table has one unit, chosen for its largest value where the scenario
// does not fix it (a wait of 2.5 s and 12 s in s, not ms); the header names it, round-off in
// a column is 0 and the terminal's ranges share the unit of their larger end.
TEST(StudyReport, AColumnIsShownInTheUnitThatReadsItsLargestValue) {
  StudySpec spec;
  spec.parameters.push_back(Parameter{"insertion.profile[1].wait"});
  const std::vector<Case> cases{{1, {{"insertion.profile[1].wait", "2500 ms"}}, {2.5}},
                                {2, {{"insertion.profile[1].wait", "12000 ms"}}, {12.0}}};
  io::Table table({{"case", "1"}, {"complete", "1"}, {inputColumnName("insertion.profile[1].wait"), "s"},
                   {"final_tip_deflection", "m"}});
  table.addRow({1.0, 1.0, 2.5, -3e-15});
  table.addRow({2.0, 1.0, 12.0, 2e-3});
  StudyResults r{spec, cases, table};
  r.display.prefer("time", "ms");
  r.display.prefer("length", "mm");
  const io::HtmlReport rep = studyReport(r, {});
  ASSERT_EQ(rep.tables.size(), 1u);
  const io::HtmlTable& t = rep.tables[0];
  EXPECT_EQ(t.header.at(1), "insertion.profile[1].wait [s]");
  EXPECT_EQ(t.header.at(2), "final_tip_deflection [mm]");
  EXPECT_EQ(t.rows.at(0).at(1), "2.5");
  EXPECT_EQ(t.rows.at(1).at(1), "12");
  EXPECT_EQ(t.rows.at(0).at(2), "0");  // round-off, not -3e-12
  EXPECT_EQ(t.rows.at(1).at(2), "2");
  const std::string overview = studyOverview(r);
  EXPECT_NE(overview.find("0 mm to 2 mm"), std::string::npos) << overview;
}
