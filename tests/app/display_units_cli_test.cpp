// What `needlesim run` shows a person: key results in the scenario's units (the unit written
// most often per dimension, or output.units), summary.json in SI, the results line naming
// the field files, and layer boundaries on the force-depth plot of report.html.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <regex>
#include <string>
#include <unistd.h>

#include <fmt/format.h>

#include "cli_run.hpp"
#include "needlesim/scenario/reader.hpp"

namespace fs = std::filesystem;
using needlesim::test::runCli;

namespace {

fs::path scratch(const std::string& name) {
  fs::path d = fs::temp_directory_path() / ("needlesim_units_" + std::to_string(::getpid())) / name;
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

std::string text(const fs::path& p) { return std::string((std::istreambuf_iterator<char>(std::ifstream(p).rdbuf())), {}); }

// A lumped scenario written in mm, N and kPa (and one output section line to append).
std::string mmNkPa(const std::string& output = "") {
  return R"(name: units_mm
tissue:
  block: {length: 40 mm, width: 60 mm, height: 60 mm}
  material: {law: neo-hookean, C10: 5 kPa, nu: 0.45}
  puncture: {force: 0.2 N}
  cutting: {force: 0.05 N}
  friction: {C_p: 2 N/m, b_p: 100 N s/m^2}
needle:
  outer_diameter: 1.2 mm
  length: 150 mm
  bevel_angle: 20 deg
  youngs_modulus: 200 GPa
  density: 7850 kg/m^3
insertion:
  profile:
    - insert: {to: 30 mm, speed: 5 mm/s}
model: {engine: lumped, time_step: 1 ms}
output:
  interval: 10 ms
)" + output;
}

fs::path write(const fs::path& dir, const std::string& yaml) {
  const fs::path f = dir / "s.yaml";
  std::ofstream(f) << yaml;
  return f;
}

// The value and unit `needlesim run` printed for `key`.
struct Printed {
  double value = NAN;
  std::string unit;
};
Printed printed(const std::string& out, const std::string& key) {
  std::smatch m;
  const std::regex line("\\n  " + key + " +(\\S+) (\\S*) ");
  if (!std::regex_search(out, m, line)) return {};
  return {std::stod(m[1]), m[2]};
}

nlohmann::json summary(const fs::path& folder) { return nlohmann::json::parse(text(folder / "summary.json")); }

}  // namespace

TEST(DisplayUnitsCli, ResultsShownInTheScenarioUnitsAndStoredInSi) {
  const fs::path d = scratch("mm");
  const auto r = runCli("run " + write(d, mmNkPa()).string() + " --out " + (d / "res").string());
  ASSERT_EQ(r.code, 0) << r.out;
  const auto s = summary(d / "res");
  // the file keeps SI with the unit named
  EXPECT_EQ(s["results"]["peak_force"]["unit"], "N");
  EXPECT_EQ(s["results"]["peak_force_depth"]["unit"], "m");
  const double depth = s["results"]["peak_force_depth"]["value"], peak = s["results"]["peak_force"]["value"];
  EXPECT_GT(depth, 1e-3);
  // the terminal in mm and N (the units the file writes most often)
  const Printed pd = printed(r.out, "peak_force_depth"), pf = printed(r.out, "peak_force");
  EXPECT_EQ(pd.unit, "mm") << r.out;
  EXPECT_NEAR(pd.value, depth / 1e-3, 1e-5 * depth / 1e-3);
  EXPECT_EQ(pf.unit, "N");
  EXPECT_NEAR(pf.value, peak, 1e-5 * peak);
  // the chosen units are recorded with the scenario, so a run of summary.json shows the same
  EXPECT_EQ(s["scenario"]["output"]["units"]["length"], "mm");
  EXPECT_EQ(s["scenario"]["output"]["units"]["stress"], "kPa");
  EXPECT_EQ(s["scenario"]["output"]["units"]["velocity"], "mm/s");
  // and the report's key-results table
  const std::string html = text(d / "res" / "report.html");
  EXPECT_NE(html.find(fmt::format("<td>{:.6g} mm</td>", depth * 1e3)), std::string::npos);
}

TEST(DisplayUnitsCli, OutputUnitsOverrideTheWrittenUnits) {
  const fs::path d = scratch("override");
  const auto r = runCli("run " + write(d, mmNkPa("  units: {length: um, force: mN}\n")).string() + " --out " +
                        (d / "res").string());
  ASSERT_EQ(r.code, 0) << r.out;
  const auto s = summary(d / "res");
  const double depth = s["results"]["peak_force_depth"]["value"], peak = s["results"]["peak_force"]["value"];
  const Printed pd = printed(r.out, "peak_force_depth"), pf = printed(r.out, "peak_force");
  EXPECT_EQ(pd.unit, "um") << r.out;
  EXPECT_NEAR(pd.value, depth / 1e-6, 1e-5 * depth / 1e-6);
  EXPECT_EQ(pf.unit, "mN");
  EXPECT_NEAR(pf.value, peak / 1e-3, 1e-5 * peak / 1e-3);
  EXPECT_EQ(s["results"]["peak_force"]["unit"], "N");  // summary.json stays SI
  // the plots' axes follow
  const std::string html = text(d / "res" / "report.html");
  EXPECT_NE(html.find("\"xlabel\":\"tip depth [um]\""), std::string::npos);
  EXPECT_NE(html.find("\"ylabel\":\"force on the needle base [mN]\""), std::string::npos);
}

// A preferred unit (here ms, from the time step) gives way to the unit that reads the value:
// 6 s of motion, not 6e+03 ms, in `check` and on the report's time axes; output.units keeps ms.
TEST(DisplayUnitsCli, DurationsAndTimeAxesInTheUnitThatReadsThem) {
  const fs::path d = scratch("seconds");
  const auto c = runCli("check " + write(d, mmNkPa()).string());
  ASSERT_EQ(c.code, 0) << c.out;
  EXPECT_NE(c.out.find(", 6 s of motion, max depth 30 mm"), std::string::npos) << c.out;
  const auto r = runCli("run " + write(d, mmNkPa()).string() + " --out " + (d / "res").string());
  ASSERT_EQ(r.code, 0) << r.out;
  const std::string html = text(d / "res" / "report.html");
  EXPECT_NE(html.find("\"xlabel\":\"time [s]\""), std::string::npos);
  EXPECT_EQ(html.find("\"xlabel\":\"time [ms]\""), std::string::npos);
  const auto fixed = runCli("check " + write(d, mmNkPa("  units: {time: ms}\n")).string());
  ASSERT_EQ(fixed.code, 0) << fixed.out;
  EXPECT_NE(fixed.out.find(", 6e+03 ms of motion"), std::string::npos) << fixed.out;
}

TEST(DisplayUnitsCli, BadOutputUnitsAreRefusedAtTheirLine) {
  const fs::path d = scratch("bad");
  const int line = 20;  // the line of "  units:" after mmNkPa's 19 lines
  struct Case {
    std::string units, message;
  } cases[] = {
      {"  units: {length: kPa}\n", "output.units.length: is a unit of stress, not of length (got 'kPa'); allowed: one of: m, cm, mm, um, nm"},
      {"  units: {force: furlong}\n", "output.units.force: is not a known unit (got 'furlong')"},
      {"  units: {length: N/m}\n", "output.units.length: is a unit of N/m, not of length (m) (got 'N/m')"},
      {"  units: {lenght: mm}\n", "output.units.lenght"},
  };
  for (const auto& c : cases) {
    const fs::path f = write(d, mmNkPa(c.units));
    const auto r = runCli("check " + f.string());
    EXPECT_EQ(r.code, 2) << r.out;
    EXPECT_NE(r.out.find(fmt::format("{}:{}:", f.string(), line)), std::string::npos) << r.out;
    EXPECT_NE(r.out.find(c.message), std::string::npos) << r.out;
  }
}

TEST(DisplayUnitsCli, ResultsLineNamesTheFilesAndTheFieldFiles) {
  const fs::path d = scratch("files");
  const auto r = runCli("run " + write(d, mmNkPa()).string() + " --out " + (d / "res").string());
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("results: " + (d / "res").string() + "/ (summary.json, forces.csv, report.html)\n"),
            std::string::npos)
      << r.out;
  const std::string rt = std::string(NEEDLESIM_SOURCE_DIR) + "/examples/realtime2d/thesis_gelatin_18G_3mms.yaml";
  const auto f = runCli("run " + rt + " --out " + (d / "rt").string());
  ASSERT_EQ(f.code, 0) << f.out;
  std::smatch m;
  ASSERT_TRUE(std::regex_search(f.out, m, std::regex("results: .*/ \\(summary\\.json, .*report\\.html, fields: (.*)\\)\\n")))
      << f.out;
  const std::string fields = m[1];
  EXPECT_NE(fields.find("tissue.xdmf"), std::string::npos) << fields;
  for (const auto& e : fs::directory_iterator(d / "rt"))
    if (e.path().extension() == ".xdmf")
      EXPECT_NE(fields.find(e.path().filename().string()), std::string::npos) << e.path();
}

TEST(DisplayUnitsCli, LayerBoundariesMarkedOnTheForceDepthPlot) {
  const fs::path d = scratch("layers");
  const std::string file = std::string(NEEDLESIM_SOURCE_DIR) + "/examples/layered_skin_fat_muscle.yaml";
  const auto r = runCli("run " + file + " --quiet --out " + (d / "res").string());
  ASSERT_EQ(r.code, 0) << r.out;
  const std::string html = text(d / "res" / "report.html");
  const auto at = html.find("const plots = "), end = html.find(";\n", at);
  ASSERT_NE(at, std::string::npos);
  const auto plots = nlohmann::json::parse(html.substr(at + 14, end - at - 14));
  const needlesim::Scenario sc = needlesim::scenario::readFile(file);
  const auto& L = sc.tissue.layers;
  ASSERT_EQ(L.size(), 4u);
  const double along = 1.0 / std::sin(sc.insertion.entry_angle);
  int depthPlots = 0;
  for (const auto& p : plots) {
    std::vector<std::pair<double, std::string>> markers;
    for (const auto& ds : p["datasets"])
      if (ds.value("marker", false)) markers.emplace_back(ds["data"][0]["x"].get<double>(), ds["label"]);
    if (p["xlabel"] != "tip depth [mm]") {
      EXPECT_TRUE(markers.empty()) << p["title"];
      continue;
    }
    ++depthPlots;
    ASSERT_EQ(markers.size(), 3u);
    double boundary = 0.0;
    for (std::size_t i = 0; i < 3; ++i) {
      boundary += L[i].thickness;  // skin 2 mm, fat 10 mm, muscle 20 mm: 2, 12 and 32 mm
      EXPECT_NEAR(markers[i].first, boundary * along * 1e3, 1e-9);
      EXPECT_EQ(markers[i].second, L[i].name + " | " + L[i + 1].name);
    }
    EXPECT_NEAR(markers[2].first, 32.0, 1e-9);
  }
  EXPECT_EQ(depthPlots, 1);
}
