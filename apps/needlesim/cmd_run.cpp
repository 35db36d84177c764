// `needlesim run [FILE]`: runs a scenario (or the built-in default) and writes
// the results folder.
#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <filesystem>

#include "commands.hpp"
#include "needlesim/core/error.hpp"
#include "needlesim/core/progress.hpp"
#include "needlesim/engines/engine.hpp"
#include "needlesim/engines/run_scenario.hpp"
#include "needlesim/scenario/reader.hpp"

namespace needlesim::app {

namespace {
struct RunArgs {
  std::string file;
  std::string out;
  bool overwrite = false;
  bool quiet = false;
};
}  // namespace

void registerRunCommand(CLI::App& app) {
  auto args = std::make_shared<RunArgs>();
  auto* cmd = app.add_subcommand("run", "Run a scenario (the built-in default when no file is given)");
  cmd->add_option("scenario", args->file, "scenario file (YAML); omit for the built-in default");
  cmd->add_option("-o,--out", args->out, "results folder (default: output.directory, else results/<name>)");
  cmd->add_flag("--overwrite", args->overwrite, "replace an existing results folder once the new one is complete");
  cmd->add_flag("-q,--quiet", args->quiet, "no progress and no summary on the terminal");
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
    if (!explicitTarget) target = io::freeResultsPath(target);
    else if (fs::exists(target) && !args->overwrite)
      throw InputError(SourceLocation{}, "--out", target.string(), "results folder already exists",
                       "a new folder, or --overwrite to replace it");
    if (!args->quiet)
      fmt::print("needlesim: running '{}' ({}) with engine '{}'\n", sc.name, sc.source, sc.model.engine);
    RunOptions opts;
    opts.progress = !args->quiet;
    RunOutcome outcome = runScenario(sc, target, args->overwrite, opts);
    if (!args->quiet) {
      for (const auto& r : outcome.results)
        fmt::print("  {:<24} {:>12.6g} {:<6} {}\n", r.key, r.value, r.unit == "1" ? "" : r.unit, r.meaning);
      fmt::print("results: {}/ (summary.json, report.html, CSV time series)\n", target.string());
    }
  });
}

void registerCheckCommand(CLI::App& app) {
  auto files = std::make_shared<std::vector<std::string>>();
  auto* cmd = app.add_subcommand("check", "Validate scenario files without running them");
  cmd->add_option("scenario", *files, "scenario files")->required();
  cmd->callback([files] {
    for (const auto& f : *files) {
      Scenario sc = scenario::readFile(f);
      if (!findEngine(sc.model.engine))
        throw InputError(SourceLocation{f, 0, 0}, "model.engine", sc.model.engine,
                         "is reserved for an engine that this build does not have yet", "lumped");
      fmt::print("{}: ok ({} layer{}, engine {}, {:.3g} s of motion, max depth {:.4g} mm)\n", f,
                 sc.tissue.layers.size(), sc.tissue.layers.size() == 1 ? "" : "s", sc.model.engine,
                 sc.totalDuration(), sc.maxDepth() * 1e3);
    }
  });
}

}  // namespace needlesim::app
