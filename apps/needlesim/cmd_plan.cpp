// `needlesim plan FILE`: plans a needle path to the scenario's plan target (docs/planning.md)
// and writes the results folder.
#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <filesystem>

#include "commands.hpp"
#include "needlesim/core/error.hpp"
#include "needlesim/core/progress.hpp"
#include "needlesim/io/folder_lock.hpp"
#include "needlesim/planning/plan_run.hpp"
#include "needlesim/planning/verify.hpp"
#include "needlesim/results/display_units.hpp"
#include "needlesim/results/results_folder.hpp"
#include "needlesim/scenario/reader.hpp"

namespace needlesim::app {
namespace {
namespace fs = std::filesystem;

struct PlanArgs {
  std::string file;
  std::string out;
  std::string verify;
  bool overwrite = false;
  bool quiet = false;
};

// Exit status of a plan that reaches no target (the folder is written all the same).
constexpr int kInfeasible = 4;

void printOutcome(const planning::PlanFolder& f, const Scenario& sc) {
  const auto& s = f.outcome.search;
  if (s.feasible)
    fmt::print("plan found: {} rotation(s), planned miss {}, in {:.3g} s ({} paths, {:.3g} paths/s)\n",
               s.best.plan.rotations(), results::shownText(s.best.miss, "m", sc.output.units, "{:.3g}"), s.seconds,
               s.paths, s.seconds > 0 ? s.paths / s.seconds : 0.0);
  else
    fmt::print("no plan: {}\n", s.reason);
  if (f.outcome.open_loop)
    fmt::print("targeting error (open loop): p50 {}, p95 {}, obstacle touch probability {:.3g}\n",
               results::shownText(f.outcome.open_loop->p50, "m", sc.output.units, "{:.3g}"),
               results::shownText(f.outcome.open_loop->p95, "m", sc.output.units, "{:.3g}"),
               f.outcome.open_loop->touch_probability);
  if (f.outcome.closed_loop)
    fmt::print("targeting error (closed loop): p50 {}, p95 {}\n",
               results::shownText(f.outcome.closed_loop->p50, "m", sc.output.units, "{:.3g}"),
               results::shownText(f.outcome.closed_loop->p95, "m", sc.output.units, "{:.3g}"));
  if (f.outcome.closed_loop && f.outcome.problem.max_retractions > 0)
    fmt::print("closed loop retractions: {:.3g} % of the insertions retract, {:.3g} per insertion\n",
               100 * f.outcome.closed_loop->retracting_share, f.outcome.closed_loop->mean_retractions);
  if (!f.verified.empty()) fmt::print("{}\n", f.verified);
  fmt::print("results: {}/\n", f.folder.string());
}

int planCommand(const PlanArgs& args) {
  installStopHandlers();
  const Scenario sc = scenario::readFile(args.file);
  if (!sc.plan.given)
    throw InputError(SourceLocation{sc.source, 0, 0}, "plan", "", "the scenario has no plan section",
                     "a plan section with a target (docs/planning.md)");
  if (!args.verify.empty()) planning::checkVerifyEngine(args.verify);
  const bool byOut = !args.out.empty();
  const fs::path chosen = byOut ? io::outputPath(args.out, "--out", commandLine()) : fs::path("results") / (sc.name + "-plan");
  const fs::path target =
      io::resolveResultsTarget(chosen, byOut ? "--out" : "", byOut ? commandLine() : SourceLocation{sc.source, 0, 0}, args.overwrite);
  const io::FolderLock lock(target, byOut ? "--out" : "name", byOut ? commandLine() : SourceLocation{sc.source, 0, 0});
  const planning::PlanFolder f = args.verify.empty()
                                     ? planning::planToFolder(sc, target, args.overwrite)
                                     : planning::planAndVerifyToFolder(sc, args.verify, target, args.overwrite);
  if (!args.quiet) printOutcome(f, sc);
  return f.outcome.search.feasible ? 0 : kInfeasible;
}

}  // namespace

void registerPlanCommand(CLI::App& app) {
  auto args = std::make_shared<PlanArgs>();
  auto* cmd = app.add_subcommand("plan", "Plan a needle path to the scenario's plan target around its obstacles "
                                         "(exit 4 when no plan reaches it; the folder says why)");
  cmd->add_option("scenario", args->file, "scenario file with a plan section (YAML)")->required();
  cmd->add_option("-o,--out", args->out, "results folder (default: results/<name>-plan)");
  cmd->add_option("--verify", args->verify,
                  "run the plan through this physics engine (realtime3d) and report the executed miss distance");
  cmd->add_flag("--overwrite", args->overwrite, "replace an existing needlesim results folder once the new one is complete");
  cmd->add_flag("-q,--quiet", args->quiet, "no summary on the terminal");
  cmd->callback([args] {
    const int code = planCommand(*args);
    if (code != 0) throw CLI::RuntimeError(code);
  });
}

}  // namespace needlesim::app
