#pragma once
// `needlesim fit`: reads data files, runs one analysis, writes fit.json and
// report.html into a new output folder and returns the table to print. The
// CLI (apps/needlesim/cmd_fit.cpp) only parses arguments into a FitRequest.
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "needlesim/core/units.hpp"
#include "needlesim/fit/hyperelastic_fit.hpp"
#include "needlesim/fit/insertion.hpp"

namespace needlesim::fit {

// Analyses accepted by --law.
const std::vector<std::string>& fitAnalyses();
// The same, as one line: "linear, neo-hookean, ...".
std::string fitAnalysesList();

struct FitRequest {
  std::vector<std::filesystem::path> data;
  std::string law;  // linear .. fung, auto, prony, toughness, friction, puncture, stiffness
  int terms = 0;
  std::filesystem::path out;  // empty: <first data file without extension>.fit next to it
  bool overwrite = false;
  bool write = true;  // false: compute only (tests)
  UniaxialReadOptions uniaxial;
  // insertion analyses
  double needleDiameter = 0.0;  // m
  double thickness = 0.0;       // m (L2 / phantom length)
  double windowStart = -1.0, windowLength = 0.0;
  bool literalEq12 = false;
  double deltaC = 0.0;  // m, cohesive opening for t_c = 2 G_c / delta_c
  double speed = 0.0;   // m/s override
  CuttingModel cutting = CuttingModel::PerSpeed;
  double dropFraction = 0.2;
};

struct FitOutcome {
  std::string table;  // for the terminal
  std::filesystem::path outDir;
  nlohmann::json json;
  std::string materialYaml;  // scenario-ready block ("" when not applicable)
};

FitOutcome runFit(const FitRequest& request);

// Parses a command-line quantity like "18 mm" into SI, checking its dimension;
// InputError naming the option otherwise.
double parseQuantityOption(const std::string& option, const std::string& text, units::Dim dim);

}  // namespace needlesim::fit
