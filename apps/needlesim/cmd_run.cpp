// `needlesim run [FILE]`: runs a scenario (or the built-in default) and writes
// the results folder.
#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <utility>

#include "commands.hpp"
#include "needlesim/core/error.hpp"
#include "needlesim/core/progress.hpp"
#include "needlesim/core/units.hpp"
#include "needlesim/engines/engine.hpp"
#include "needlesim/engines/run_scenario.hpp"
#include "needlesim/results/checkpoint.hpp"
#include "needlesim/io/folder_lock.hpp"
#include "needlesim/planning/plan_problem.hpp"
#include "needlesim/results/display_units.hpp"
#include "needlesim/scenario/reader.hpp"
#include "needlesim/study/study.hpp"

namespace needlesim::app {

namespace {
namespace fs = std::filesystem;

struct RunArgs {
  std::string file;
  std::string out;
  bool overwrite = false;
  bool quiet = false;
  bool resume = false;
};

// Where the results go and which input named it (for messages).
struct Target {
  fs::path path;
  std::string field;  // "--out" or "output.directory"; empty for the automatic results/<name>
};

Target chooseTarget(const RunArgs& args, const Scenario& sc) {
  if (!args.out.empty()) return {io::outputPath(args.out, "--out", commandLine()), "--out"};
  if (!sc.output.directory.empty()) return {io::outputPath(sc.output.directory, "output.directory", sc.where("output.directory")), "output.directory"};
  return {fs::path("results") / sc.name, ""};
}

// A fresh run over the checkpoint of an interrupted one: only with --overwrite,
// and only a folder needlesim wrote as a checkpoint is deleted.
void clearCheckpointInTheWay(const fs::path& ckFolder, bool overwrite) {
  if (!overwrite)
    throw InputError(SourceLocation{ckFolder.string(), 0, 0}, "", "",
                     "the checkpoint of an interrupted run of this scenario is in the way",
                     "needlesim run --resume to continue it, or --overwrite (or deleting the folder) to start afresh");
  if (!io::isCheckpointFolder(ckFolder))
    throw InputError(commandLine(), "--overwrite", ckFolder.string(),
                     "is " + io::describeContents(ckFolder) + ", not a needlesim checkpoint folder; it is not deleted",
                     "--overwrite deletes only a checkpoint folder needlesim wrote (state.bin and .h5 copies); move "
                     "it away or choose another --out");
  fs::remove_all(ckFolder);
}

// What an interrupted run leaves and how to go on, for the error line.
std::string afterInterruption(const RunArgs& args, const fs::path& target, const fs::path& ckFolder) {
  std::string msg = "; nothing was written to " + target.string();
  if (!io::isCheckpointFolder(ckFolder) || !fs::exists(ckFolder / "state.bin"))
    return msg + " and nothing else was kept: run it again for results";
  std::string again = "needlesim run";
  if (!args.file.empty()) again += " " + args.file;
  if (!args.out.empty()) again += " --out " + target.string();  // else the scenario names the same target again
  return msg + fmt::format("; the checkpoint {} is kept: continue with {} --resume", ckFolder.string(), again);
}

// The folder's files as a person looks for them: summary.json, the tables, the report, then
// the field files to open in ParaView (the .xdmf of each .xdmf/.h5 pair).
std::string folderContents(const std::vector<std::string>& files) {
  const auto has = [&](const std::string& f) { return std::find(files.begin(), files.end(), f) != files.end(); };
  const auto endingIn = [&](std::string_view ext) {
    std::vector<std::string> out;
    for (const auto& f : files)
      if (f.ends_with(ext)) out.push_back(f);
    return out;
  };
  std::vector<std::string> shown;
  if (has("summary.json")) shown.emplace_back("summary.json");
  for (const auto& f : endingIn(".csv")) shown.push_back(f);
  if (has("report.html")) shown.emplace_back("report.html");
  std::string text = fmt::format("{}", fmt::join(shown, ", "));
  const std::vector<std::string> fields = endingIn(".xdmf");
  if (!fields.empty()) text += fmt::format(", fields: {}", fmt::join(fields, ", "));
  return text;
}

void printResults(const RunOutcome& outcome, const Scenario& sc, const RunArgs& args,
                  const io::Checkpoint& checkpoint, const fs::path& ckFolder) {
  for (const auto& r : outcome.results) {
    const units::Shown s = units::shown(r.value, r.unit, sc.output.units);
    fmt::print("  {:<24} {:>12.6g} {:<6} {}\n", r.key, s.value, s.unit == "1" ? "" : s.unit, r.meaning);
  }
  if (args.resume)
    fmt::print("resumed from t = {:.6g} s (step {}) of {}\n", checkpoint.resumedTime(), checkpoint.resumedSteps(),
               ckFolder.string());
  fmt::print("results: {}/ ({})\n", outcome.folder.string(), folderContents(outcome.files));
}

// The checked target the results go to (before the run: InputError for a path
// that cannot be written or is in use) and its checkpoint folder.
std::pair<fs::path, fs::path> resolveTarget(const RunArgs& args, const Scenario& sc) {
  const Target target = chooseTarget(args, sc);
  // The checkpoint belongs to the target as named (for the automatic one,
  // results/<name>, whichever free -2, -3 ... name the results then get).
  const fs::path ckFolder = io::Checkpoint::folderFor(target.path);
  const SourceLocation where = target.field.empty() ? SourceLocation{sc.source, 0, 0}
                               : target.field == "--out" ? commandLine()
                                                         : sc.where(target.field);
  return {io::resolveResultsTarget(target.path, target.field, where, args.overwrite), ckFolder};
}

void runCommand(const RunArgs& args) {
  if (!args.file.empty()) {  // before the scenario, its meshes or any output is touched
    const EngineInfo* named = findEngine(scenario::engineNamedIn(args.file));
    if (named && named->openmp) chooseOpenMpWait();
  }
  installStopHandlers();  // Ctrl-C while the scenario's geometry is read and meshed stops it too
  Scenario sc = args.file.empty() ? scenario::defaultScenario() : scenario::readFile(args.file);
  const auto [targetPath, ckFolder] = resolveTarget(args, sc);
  // One writer per folder: held until the results are in place (a second run into it is refused).
  const bool byOut = !args.out.empty(), byDirectory = !byOut && !sc.output.directory.empty();
  const io::FolderLock lock(targetPath, byOut ? "--out" : byDirectory ? "output.directory" : "name",
                            byOut ? commandLine() : byDirectory ? sc.where("output.directory") : SourceLocation{sc.source, 0, 0});
  const EngineInfo* engine = findEngine(sc.model.engine);
  const bool checkpoints = engine && engine->checkpoints && sc.output.checkpoint_interval > 0;
  if (args.resume && !(engine && engine->checkpoints))
    throw InputError(SourceLocation{sc.source, 0, 0}, "--resume", sc.model.engine,
                     "this engine does not write checkpoints, so there is nothing to resume", "engine mpm");
  if (!args.resume && checkpoints && fs::exists(ckFolder)) clearCheckpointInTheWay(ckFolder, args.overwrite);
  io::Checkpoint checkpoint({ckFolder, io::scenarioFingerprint(sc), sc.output.checkpoint_interval, 0, args.resume,
                             !args.quiet});
  if (args.resume) checkpoint.check(sc.model.engine);
  io::removeStaleStages(targetPath.parent_path().empty() ? fs::path(".") : targetPath.parent_path());
  if (!args.quiet)
    fmt::print("needlesim: {} '{}' ({}) with engine '{}'\n", args.resume ? "resuming" : "running", sc.name, sc.source,
               sc.model.engine);
  RunOptions opts;
  opts.progress = !args.quiet;
  opts.printWarnings = !args.quiet;
  if (checkpoints || args.resume) opts.checkpoint = &checkpoint;
  exitOnStopInBlockingCalls(afterInterruption(args, targetPath, ckFolder));  // a stop inside a factorisation
  try {
    const RunOutcome outcome = runScenario(sc, targetPath, args.overwrite, opts);
    if (!args.quiet) printResults(outcome, sc, args, checkpoint, ckFolder);
  } catch (const RunInterrupted& e) {
    throw RunInterrupted(e.what() + afterInterruption(args, targetPath, ckFolder), e.signal());
  }
}
}  // namespace

void registerRunCommand(CLI::App& app) {
  auto args = std::make_shared<RunArgs>();
  auto* cmd = app.add_subcommand("run", "Run a scenario (the built-in default when no file is given)");
  cmd->add_option("scenario", args->file, "scenario file (YAML); omit for the built-in default");
  cmd->add_option("-o,--out", args->out, "results folder (default: output.directory, else results/<name>)");
  cmd->add_flag("--overwrite", args->overwrite,
                "replace an existing needlesim results folder once the new one is complete (nothing else is deleted)");
  cmd->add_flag("-q,--quiet", args->quiet, "no progress, warnings or summary on the terminal");
  cmd->add_flag("--resume", args->resume,
                "continue an interrupted run from its checkpoint (<results folder>.checkpoint, written every "
                "output.checkpoint_interval and when stopped with Ctrl-C)");
  cmd->callback([args] { runCommand(*args); });
}

// The files `check` reads: each file as given, each folder as every *.yaml below it
// (recursively, sorted by path).
static std::vector<std::string> filesToCheck(const std::vector<std::string>& args) {
  std::vector<std::string> out;
  for (const auto& a : args) {
    std::error_code ec;
    if (!fs::is_directory(a, ec)) {
      out.push_back(a);
      continue;
    }
    std::vector<std::string> found;
    for (auto it = fs::recursive_directory_iterator(a, ec); !ec && it != fs::recursive_directory_iterator();
         it.increment(ec))
      if (it->path().extension() == ".yaml" && it->is_regular_file()) found.push_back(it->path().string());
    if (ec)
      throw InputError(commandLine(), "file", a, "is a folder that cannot be read: " + ec.message(),
                       "a readable folder, or scenario and study files");
    if (found.empty())
      throw InputError(commandLine(), "file", a, "is a folder with no .yaml file below it",
                       "a folder holding scenario or study files (*.yaml), or the files themselves");
    std::sort(found.begin(), found.end());
    out.insert(out.end(), found.begin(), found.end());
  }
  return out;
}

void registerCheckCommand(CLI::App& app) {
  auto args = std::make_shared<std::vector<std::string>>();
  auto* cmd = app.add_subcommand("check", "Validate scenario and study files without running them");
  cmd->add_option("file", *args,
                  "scenario or study files (a study is recognised by its 'vary' list), or folders: every *.yaml "
                  "below them")
      ->required();
  cmd->callback([args] {
    installStopHandlers();  // Ctrl-C while a geometry is read and meshed: the clean stop (exit 130)
    exitOnStopInBlockingCalls("; the files after it were not checked");  // a stop inside an engine's set-up
    const std::vector<std::string> files = filesToCheck(*args);
    int bad = 0;
    for (const auto& f : files) {
      try {
        if (study::isStudyFile(f)) {
          study::StudySpec spec = study::readStudyFile(f);
          std::ifstream in(spec.scenario_file);
          std::string base((std::istreambuf_iterator<char>(in)), {});
          auto cases = study::expandCases(spec, base, study::CaseCheck::Representative);
          std::size_t read = study::representativeCases(spec, cases).size();
          fmt::print("{}: ok (study of {} case{} on {}; {} read as scenarios: the first, each field's smallest and "
                     "largest value and each unit or word written; sweep reads every case before running)\n",
                     f, cases.size(), cases.size() == 1 ? "" : "s", spec.scenario_file.string(), read);
          continue;
        }
        Scenario sc = scenario::readFile(f);
        if (sc.plan.given) {  // a scenario for `needlesim plan`: what the planner needs (docs/planning.md)
          const planning::PlanProblem pb = planning::planProblem(sc);
          fmt::print("{}: ok (plan: target at depth {}, {} obstacle(s), curvature {:.4g} 1/m; for needlesim plan)\n", f,
                     results::shownText(pb.target.x(), "m", sc.output.units, "{:.4g}"), pb.obstacles.size(), pb.kappa);
          continue;
        }
        // refuses what the engine does not model and what its steps do not resolve, as run would
        const StepEstimate estimate = preflight(sc);
        fmt::print("{}: ok ({} layer{}, engine {}, {} of motion, max depth {}; estimate: {})\n", f,
                   sc.tissue.layers.size(), sc.tissue.layers.size() == 1 ? "" : "s", sc.model.engine,
                   results::shownText(sc.totalDuration(), "s", sc.output.units, "{:.3g}"),
                   results::shownText(sc.maxDepth(), "m", sc.output.units, "{:.4g}"), estimate.text());
      } catch (const InputError& e) {
        fmt::print(stderr, "error: {}\n", e.what());
        ++bad;
      }
    }
    if (bad > 0)
      throw InputError(commandLine(), "", "", fmt::format("{} of {} files have errors (listed above)", bad, files.size()),
                       "fix them and run needlesim check again");
  });
}

}  // namespace needlesim::app
