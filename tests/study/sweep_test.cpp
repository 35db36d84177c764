// Parameter studies: samplers, case expansion, results against the closed
// form of the lumped model, resume after a lost case, bad studies, and MPI.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
#include <sys/wait.h>

#include "needlesim/core/error.hpp"
#include "needlesim/io/table.hpp"
#include "needlesim/study/samplers.hpp"
#include "needlesim/study/study.hpp"

using namespace needlesim;
using namespace needlesim::study;
namespace fs = std::filesystem;

namespace {

fs::path scratch(const std::string& name) {
  fs::path d = fs::temp_directory_path() / ("needlesim_sweep_" + std::to_string(::getpid())) / name;
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

fs::path writeStudy(const fs::path& dir, const std::string& body) {
  fs::path f = dir / "study.yaml";
  std::ofstream(f) << "scenario: " << NEEDLESIM_SOURCE_DIR << "/examples/gelatin_18G_3mms.yaml\n"
                   << "directory: " << (dir / "out").string() << "\n"
                   << body;
  return f;
}

// study.csv back as rows of numbers.
std::vector<std::vector<double>> readCsv(const fs::path& f, std::vector<std::string>& header) {
  std::ifstream in(f);
  std::string line;
  std::getline(in, line);
  std::stringstream hs(line);
  std::string cell;
  while (std::getline(hs, cell, ',')) header.push_back(cell);
  std::vector<std::vector<double>> rows;
  while (std::getline(in, line)) {
    std::stringstream ss(line);
    std::vector<double> r;
    while (std::getline(ss, cell, ',')) r.push_back(std::stod(cell));
    rows.push_back(r);
  }
  return rows;
}

std::size_t col(const std::vector<std::string>& h, const std::string& prefix) {
  for (std::size_t i = 0; i < h.size(); ++i)
    if (h[i].rfind(prefix, 0) == 0) return i;
  ADD_FAILURE() << "no column " << prefix;
  return 0;
}

}  // namespace

TEST(Samplers, GridVisitsEveryCombinationOnce) {
  auto g = gridIndices({2, 3, 1});
  ASSERT_EQ(g.size(), 6u);
  std::set<std::vector<int>> unique(g.begin(), g.end());
  EXPECT_EQ(unique.size(), 6u);
  EXPECT_EQ(g.back(), (std::vector<int>{1, 2, 0}));
}

TEST(Samplers, LatinHypercubeHasOneSampleInEveryStratum) {
  const int n = 50, d = 4;
  auto s = latinHypercube(n, d, 42);
  for (int j = 0; j < d; ++j) {
    std::set<int> strata;
    for (int i = 0; i < n; ++i) {
      ASSERT_GE(s[i][j], 0.0);
      ASSERT_LT(s[i][j], 1.0);
      strata.insert(static_cast<int>(s[i][j] * n));
    }
    EXPECT_EQ(strata.size(), static_cast<std::size_t>(n)) << "dimension " << j;
  }
  EXPECT_EQ(latinHypercube(n, d, 42), s);  // deterministic for a seed
  EXPECT_NE(latinHypercube(n, d, 43), s);
}

// Every case's exit force equals F_cut + L (C_p + b_p v) (seed 003 eq 5.1),
// so the study really changed the field it names.
TEST(Sweep, GridCasesFollowTheClosedFormOfEachCase) {
  fs::path dir = scratch("grid");
  auto spec = readStudyFile(writeStudy(dir, R"(method: grid
vary:
  - {field: "insertion.profile[0].insert.speed", values: [2.5 mm/s, 10 mm/s]}
  - {field: tissue.friction.C_p, values: [2 N/m, 3 N/m, 5 N/m]}
)"));
  SweepOptions opt;
  opt.progress = false;
  auto rep = runSweep(spec, opt);
  EXPECT_EQ(rep.cases, 6);
  EXPECT_TRUE(rep.failed.empty());
  std::vector<std::string> h;
  auto rows = readCsv(dir / "out" / "study.csv", h);
  ASSERT_EQ(rows.size(), 6u);
  for (const auto& r : rows) {
    double v = r[col(h, "input: insertion.profile[0].insert.speed")], C = r[col(h, "input: tissue.friction.C_p")];
    double expected = 0.04335 + 0.055 * (C + 285.053 * v);
    EXPECT_NEAR(r[col(h, "exit_force")], expected, 2e-3 * expected) << "v " << v << " C " << C;
  }
  EXPECT_TRUE(fs::exists(dir / "out" / "report.html"));
  EXPECT_TRUE(fs::exists(dir / "out" / "cases" / "case_0006" / "forces.csv"));
  // A second run into the same folder is refused, not overwritten.
  EXPECT_THROW(runSweep(spec, opt), InputError);
}

TEST(Sweep, OneAtATimeChangesEachParameterByItsPercentages) {
  fs::path dir = scratch("oat");
  auto spec = readStudyFile(writeStudy(dir, R"(method: one-at-a-time
vary:
  - {field: tissue.friction.C_p, percent: [-10, 10]}
  - {field: tissue.cutting.force, percent: [20]}
)"));
  std::ifstream in(spec.scenario_file);
  std::string base((std::istreambuf_iterator<char>(in)), {});
  auto cases = expandCases(spec, base);
  ASSERT_EQ(cases.size(), 4u);  // base + 2 + 1
  EXPECT_NEAR(cases[0].values_si[0], 3.791, 1e-12);
  EXPECT_NEAR(cases[1].values_si[0], 3.791 * 0.9, 1e-12);
  EXPECT_NEAR(cases[2].values_si[0], 3.791 * 1.1, 1e-12);
  EXPECT_NEAR(cases[3].values_si[1], 0.04335 * 1.2, 1e-12);
  EXPECT_NEAR(cases[3].values_si[0], 3.791, 1e-12);
}

TEST(Sweep, ResumeRerunsOnlyTheMissingCase) {
  fs::path dir = scratch("resume");
  auto spec = readStudyFile(writeStudy(dir, R"(method: list
vary:
  - {field: tissue.friction.C_p, values: [2 N/m, 3 N/m, 4 N/m]}
  - {field: tissue.friction.b_p, values: [200 N s/m^2, 250 N s/m^2, 300 N s/m^2]}
)"));
  SweepOptions opt;
  opt.progress = false;
  runSweep(spec, opt);
  fs::remove_all(dir / "out" / "cases" / "case_0002");  // a lost case
  opt.resume = true;
  auto rep = runSweep(spec, opt);
  EXPECT_EQ(rep.ran, 1);
  EXPECT_EQ(rep.reused, 2);
  EXPECT_TRUE(rep.failed.empty());
}

TEST(Sweep, BadStudiesNameTheProblem) {
  fs::path dir = scratch("bad");
  auto expectMsg = [&](const std::string& body, const std::string& part) {
    try {
      auto spec = readStudyFile(writeStudy(dir, body));
      std::ifstream in(spec.scenario_file);
      std::string base((std::istreambuf_iterator<char>(in)), {});
      expandCases(spec, base);
      ADD_FAILURE() << "no error for " << body;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << e.what();
    }
  };
  expectMsg("vary:\n  - {field: tissue.friction.C_p, values: [-1 N/m]}\n", "case 1");
  expectMsg("vary:\n  - {field: tissue.friction.C_p, values: [3 mm]}\n", "wrong unit");
  expectMsg("vary:\n  - {field: tissue.friction.C_p}\n", "values");
  expectMsg("method: latin-hypercube\nvary:\n  - {field: tissue.friction.C_p, min: 3 N/m, max: 2 N/m}\n", "larger than min");
  expectMsg("vary:\n  - {field: \"insertion.profile[7].insert.speed\", values: [1 mm/s]}\n", "no entry [7]");
  expectMsg("vary:\n  - {feild: x}\n", "not a known field");
}

TEST(Sweep, TwoMpiRanksShareTheCasesAndRankZeroGathers) {
  std::string mpiexec = NEEDLESIM_MPIEXEC;
  if (mpiexec.empty()) GTEST_SKIP() << "built without MPI";
  fs::path dir = scratch("mpi");
  fs::path f = writeStudy(dir, "method: grid\nvary:\n  - {field: tissue.friction.C_p, values: [2 N/m, 3 N/m, 4 N/m, 5 N/m, 6 N/m]}\n");
  std::string cmd = mpiexec + " --allow-run-as-root --oversubscribe -n 2 " + NEEDLESIM_BINARY + " sweep -q " +
                    f.string() + " > " + (dir / "log.txt").string() + " 2>&1";
  int status = std::system(cmd.c_str());
  ASSERT_TRUE(WIFEXITED(status));
  ASSERT_EQ(WEXITSTATUS(status), 0) << std::ifstream(dir / "log.txt").rdbuf();
  std::vector<std::string> h;
  auto rows = readCsv(dir / "out" / "study.csv", h);
  ASSERT_EQ(rows.size(), 5u);
  for (const auto& r : rows) EXPECT_EQ(r[col(h, "complete")], 1.0);
}
