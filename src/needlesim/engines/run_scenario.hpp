#pragma once
// Runs one scenario with its engine into a results folder: the one path that
// `needlesim run` and every case of `needlesim sweep` go through.
#include <filesystem>
#include <vector>

#include "needlesim/engines/engine.hpp"
#include "needlesim/results/results_folder.hpp"

namespace needlesim {

struct RunOutcome {
  std::filesystem::path folder;
  std::vector<io::KeyResult> results;
  std::vector<std::pair<std::string, io::Table>> tables;  // as written to <name>.csv
  double wall_seconds = 0.0;
  std::vector<std::string> files;  // written into the folder: summary.json, CSVs, report.html, fields
};

// Throws InputError if the engine is not in this build, SolverError if it stops
// (its results up to there committed as "stopped"), RunInterrupted on a stop
// request and Error when a file cannot be written (both: nothing committed).
RunOutcome runScenario(const Scenario& scenario, const std::filesystem::path& target, bool overwrite,
                       const RunOptions& options);

}  // namespace needlesim
