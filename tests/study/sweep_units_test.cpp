// A study's report shows its values in the base scenario's units (mm/s, mm, N for the
// gelatin example); study.csv keeps SI.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <unistd.h>

#include "needlesim/study/study.hpp"

namespace fs = std::filesystem;
using namespace needlesim;

TEST(SweepUnits, ReportPlotsInTheScenarioUnitsAndCsvInSi) {
  const fs::path dir = fs::temp_directory_path() / ("needlesim_sweep_units_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::ofstream(dir / "study.yaml") << "scenario: " << NEEDLESIM_SOURCE_DIR << "/examples/gelatin_18G_3mms.yaml\n"
                                    << "directory: " << (dir / "out").string() << "\n"
                                    << "method: list\nvary:\n"
                                    << "  - {field: \"insertion.profile[0].insert.speed\", values: [2.5 mm/s, 10 mm/s]}\n";
  study::SweepOptions opt;
  opt.progress = false;
  const auto rep = study::runSweep(study::readStudyFile(dir / "study.yaml"), opt);
  ASSERT_TRUE(rep.failed.empty());
  std::ifstream csv(dir / "out" / "study.csv");
  std::string header;
  std::getline(csv, header);
  EXPECT_NE(header.find("insertion.profile[0].insert.speed [m/s]"), std::string::npos) << header;

  std::ifstream in(dir / "out" / "report.html");
  const std::string html((std::istreambuf_iterator<char>(in)), {});
  const auto at = html.find("const plots = "), end = html.find(";\n", at);
  ASSERT_NE(at, std::string::npos);
  const auto plots = nlohmann::json::parse(html.substr(at + 14, end - at - 14));
  bool sawForce = false, sawDepth = false;
  for (const auto& p : plots) {
    EXPECT_EQ(p["xlabel"], "insertion.profile[0].insert.speed [mm/s]");
    const auto& data = p["datasets"][0]["data"];
    ASSERT_EQ(data.size(), 2u);
    EXPECT_NEAR(data[0]["x"].get<double>(), 2.5, 1e-12);
    EXPECT_NEAR(data[1]["x"].get<double>(), 10.0, 1e-12);
    if (p["ylabel"] == "exit_force [N]") sawForce = true;
    if (p["ylabel"] == "peak_force_depth [mm]") {
      sawDepth = true;
      EXPECT_GT(data[0]["y"].get<double>(), 1.0);  // millimetres, not metres
    }
  }
  EXPECT_TRUE(sawForce);
  EXPECT_TRUE(sawDepth);
  fs::remove_all(dir);
}
