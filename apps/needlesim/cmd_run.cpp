// `needlesim run [FILE]`: runs a scenario (or the built-in default) and writes
// the results folder.
#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <filesystem>
#include <fstream>
#include <iterator>

#include "commands.hpp"
#include "needlesim/core/error.hpp"
#include "needlesim/core/progress.hpp"
#include "needlesim/engines/engine.hpp"
#include "needlesim/engines/run_scenario.hpp"
#include "needlesim/io/checkpoint.hpp"
#include "needlesim/scenario/reader.hpp"
#include "needlesim/study/study.hpp"

namespace needlesim::app {

namespace {
struct RunArgs {
  std::string file;
  std::string out;
  bool overwrite = false;
  bool quiet = false;
  bool resume = false;
};
}  // namespace

void registerRunCommand(CLI::App& app) {
  auto args = std::make_shared<RunArgs>();
  auto* cmd = app.add_subcommand("run", "Run a scenario (the built-in default when no file is given)");
  cmd->add_option("scenario", args->file, "scenario file (YAML); omit for the built-in default");
  cmd->add_option("-o,--out", args->out, "results folder (default: output.directory, else results/<name>)");
  cmd->add_flag("--overwrite", args->overwrite, "replace an existing results folder once the new one is complete");
  cmd->add_flag("-q,--quiet", args->quiet, "no progress and no summary on the terminal");
  cmd->add_flag("--resume", args->resume,
                "continue an interrupted run from its checkpoint (<results folder>.checkpoint, written every "
                "output.checkpoint_interval)");
  cmd->callback([args] {
    Scenario sc = args->file.empty() ? scenario::defaultScenario() : scenario::readFile(args->file);
    namespace fs = std::filesystem;
    fs::path target;
    bool explicitTarget = true;
    if (!args->out.empty()) target = args->out;
    else if (!sc.output.directory.empty()) target = sc.output.directory;
    else {
      target = fs::path("results") / sc.name;
      explicitTarget = false;
    }
    // The checkpoint belongs to the target as named (for the automatic one,
    // results/<name>, whichever free -2, -3 ... name the results then get).
    const fs::path ckFolder = io::Checkpoint::folderFor(target);
    if (!explicitTarget) target = io::freeResultsPath(target);
    else if (fs::exists(target) && !args->overwrite)
      throw InputError(SourceLocation{}, "--out", target.string(), "results folder already exists",
                       "a new folder, or --overwrite to replace it");
    const EngineInfo* engine = findEngine(sc.model.engine);
    const bool checkpoints = engine && engine->checkpoints && sc.output.checkpoint_interval > 0;
    if (args->resume && !(engine && engine->checkpoints))
      throw InputError(SourceLocation{sc.source, 0, 0}, "--resume", sc.model.engine,
                       "this engine does not write checkpoints, so there is nothing to resume", "engine mpm");
    if (!args->resume && checkpoints && fs::exists(ckFolder)) {
      if (!args->overwrite)
        throw InputError(SourceLocation{ckFolder.string(), 0, 0}, "", "",
                         "the checkpoint of an interrupted run of this scenario is in the way",
                         "needlesim run --resume to continue it, or --overwrite (or deleting the folder) to start afresh");
      fs::remove_all(ckFolder);
    }
    io::Checkpoint checkpoint({ckFolder, io::scenarioFingerprint(sc), sc.output.checkpoint_interval, 0, args->resume,
                               !args->quiet});
    if (args->resume) checkpoint.check(sc.model.engine);
    if (!args->quiet)
      fmt::print("needlesim: {} '{}' ({}) with engine '{}'\n", args->resume ? "resuming" : "running", sc.name,
                 sc.source, sc.model.engine);
    RunOptions opts;
    opts.progress = !args->quiet;
    if (checkpoints || args->resume) opts.checkpoint = &checkpoint;
    RunOutcome outcome = runScenario(sc, target, args->overwrite, opts);
    if (args->resume) io::removeAbandonedStages(target);  // what the killed run had staged
    if (!args->quiet) {
      for (const auto& r : outcome.results)
        fmt::print("  {:<24} {:>12.6g} {:<6} {}\n", r.key, r.value, r.unit == "1" ? "" : r.unit, r.meaning);
      if (args->resume)
        fmt::print("resumed from t = {:.6g} s (step {}) of {}\n", checkpoint.resumedTime(), checkpoint.resumedSteps(),
                   ckFolder.string());
      fmt::print("results: {}/ (summary.json, report.html, CSV time series)\n", target.string());
    }
  });
}

void registerCheckCommand(CLI::App& app) {
  auto files = std::make_shared<std::vector<std::string>>();
  auto* cmd = app.add_subcommand("check", "Validate scenario and study files without running them");
  cmd->add_option("file", *files, "scenario or study files (a study is recognised by its 'vary' list)")->required();
  cmd->callback([files] {
    int bad = 0;
    for (const auto& f : *files) {
      try {
        if (study::isStudyFile(f)) {
          study::StudySpec spec = study::readStudyFile(f);
          std::ifstream in(spec.scenario_file);
          std::string base((std::istreambuf_iterator<char>(in)), {});
          auto cases = study::expandCases(spec, base);  // reads every case as a scenario
          fmt::print("{}: ok (study of {} cases on {})\n", f, cases.size(), spec.scenario_file.string());
          continue;
        }
        Scenario sc = scenario::readFile(f);
        // refuses what the engine does not model and what its steps do not resolve, as run would
        const StepEstimate estimate = preflight(sc);
        fmt::print("{}: ok ({} layer{}, engine {}, {:.3g} s of motion, max depth {:.4g} mm; estimate: {})\n", f,
                   sc.tissue.layers.size(), sc.tissue.layers.size() == 1 ? "" : "s", sc.model.engine,
                   sc.totalDuration(), sc.maxDepth() * 1e3, estimate.text());
      } catch (const InputError& e) {
        fmt::print(stderr, "error: {}\n", e.what());
        ++bad;
      }
    }
    if (bad > 0)
      throw InputError(SourceLocation{}, "", "", fmt::format("{} of {} files have errors (listed above)", bad, files->size()),
                       "fix them and run needlesim check again");
  });
}

}  // namespace needlesim::app
