#pragma once
// `needlesim plan` end to end: the scenario's plan section searched (planner.hpp), the chosen
// plan's targeting error predicted (uncertainty.hpp), and everything reported through a
// ResultSink: plan.csv, path.csv, error_distribution.csv, the results, three projections and
// the error histogram for report.html, and the path as a polyline for ParaView.
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "needlesim/planning/planner.hpp"
#include "needlesim/planning/uncertainty.hpp"
#include "needlesim/results/result_sink.hpp"

namespace needlesim {
struct Scenario;
}

namespace needlesim::planning {

struct PlanOutcome {
  PlanProblem problem;
  SearchResult search;  // search.best: the plan chosen (or the closest approach)
  std::optional<ErrorDistribution> open_loop, closed_loop;
  std::string chosen_by;  // "clearance" or "risk"
};

// Searches the scenario's plan section and predicts the chosen plan's targeting error.
// InputError for a scenario that cannot be planned.
PlanOutcome planScenario(const Scenario& sc);

// Tables, results, plots, notes and the path polyline of an outcome.
void reportPlan(const Scenario& sc, const PlanOutcome& outcome, ResultSink& sink);

// The scenario with its insertion replaced by the plan: entry offset and angle, the bevel's
// roll, one insert per arc (duty-cycled where the arc's curvature is below the needle's), a
// retraction before an arc that has one and an axial rotation before each arc after the first. Any engine runs it (--verify, the tests).
Scenario planAsScenario(const Scenario& sc, const Plan& plan, double kappa);

struct PlanFolder {
  std::filesystem::path folder;
  std::vector<std::string> files;
  PlanOutcome outcome;
  std::string verified;  // --verify: what the physics engine executed (verify.hpp)
};
// Plans and writes the results folder (results/results_folder.hpp) at `target`.
PlanFolder planToFolder(const Scenario& sc, const std::filesystem::path& target, bool overwrite);

}  // namespace needlesim::planning
