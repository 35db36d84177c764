#pragma once
// `needlesim fit`: reads data files, runs one analysis, writes fit.json and
// report.html into a results folder (staged and moved into place like the
// folder of `needlesim run`) and returns the table to print. The CLI
// (apps/needlesim/cmd_fit.cpp) only parses arguments into a FitRequest.
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
  std::filesystem::path out;  // --out; empty: results/<fitResultsName(data, law)> (-2, -3 ... if taken)
  bool overwrite = false;     // replace a results folder at `out`
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

// The most characters the data files' stems take in fitResultsName.
inline constexpr std::size_t kMaxFitNameStems = 64;

// The default results folder name of a fit: "fit_" + the data files' stems in
// order, joined by '+', + "_" + the analysis (fit_plastisol_compression_auto,
// fit_gelatin_3mms+gelatin_5mms_friction). Characters other than letters,
// digits, '.', '-', '_' and non-ASCII ones become '_'. Stems longer than
// kMaxFitNameStems together keep the whole stems that fit (at least the
// first, cut to that length) and end in "+N_more" for the N left out and
// "-HASH", 8 hex digits of the full list of stems, so that no two lists share
// a name by being cut alike.
std::string fitResultsName(const std::vector<std::filesystem::path>& data, const std::string& law);

// Parses a command-line quantity like "18 mm" into SI, checking its dimension;
// InputError naming the option otherwise.
double parseQuantityOption(const std::string& option, const std::string& text, units::Dim dim);

}  // namespace needlesim::fit
