// `needlesim sweep STUDY.yaml`: a parameter study over any engine. Cases run
// on all cores; under `mpirun -n N` ranks share the cases and rank 0 gathers.
#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <cstdlib>
#include <fstream>
#include <iterator>

#include "commands.hpp"
#include "needlesim/core/error.hpp"
#include "needlesim/core/progress.hpp"
#include "needlesim/scenario/reader.hpp"
#include "needlesim/study/study.hpp"

#ifdef NEEDLESIM_WITH_MPI
#include <mpi.h>
#endif

namespace needlesim::app {

namespace {
struct SweepArgs {
  std::string file;
  std::string out;
  bool resume = false;
  bool overwrite = false;
  bool quiet = false;
  int parallel = -1;
};

// True when launched by mpirun (Open MPI sets these for every rank).
bool launchedByMpi() { return std::getenv("OMPI_COMM_WORLD_SIZE") || std::getenv("PMI_SIZE"); }
}  // namespace

void registerSweepCommand(CLI::App& app) {
  auto a = std::make_shared<SweepArgs>();
  auto* cmd = app.add_subcommand("sweep", "Run a parameter study (grid, list, one-at-a-time, latin hypercube)");
  cmd->add_option("study", a->file, "study file (YAML; see docs/studies.md)")->required();
  cmd->add_option("-o,--out", a->out, "study folder (default: the study file's directory, else results/<name>)");
  cmd->add_flag("--resume", a->resume, "reuse completed cases of an earlier, interrupted or failed run");
  cmd->add_flag("--overwrite", a->overwrite,
                "replace an earlier study in the study folder (only a folder a sweep wrote is deleted)");
  cmd->add_option("-j,--parallel", a->parallel, "cases at once per process (default: study.parallel, else all cores)");
  cmd->add_flag("-q,--quiet", a->quiet, "no progress on the terminal");
  cmd->callback([a] {
    chooseOpenMpWait();  // a sweep's cases may run OpenMP engines side by side (openmp_wait.cpp)
    study::StudySpec spec = study::readStudyFile(a->file);
    if (a->parallel >= 0) spec.parallel = a->parallel;
    study::SweepOptions opt;
    opt.resume = a->resume;
    opt.overwrite = a->overwrite;
    opt.out = a->out;
    opt.progress = !a->quiet;
    bool mpi = false;
    if (a->overwrite && launchedByMpi())
      throw InputError(commandLine(), "--overwrite", "", "cannot be used under mpirun: the ranks share the study folder",
                       "remove the study folder, or choose another --out");
#ifdef NEEDLESIM_WITH_MPI
    if (launchedByMpi()) {
      MPI_Init(nullptr, nullptr);
      MPI_Comm_rank(MPI_COMM_WORLD, &opt.rank);
      MPI_Comm_size(MPI_COMM_WORLD, &opt.ranks);
      mpi = true;
      opt.resume = true;  // ranks share one study folder
      opt.progress = opt.progress && opt.rank == 0;
    }
#else
    if (launchedByMpi())
      fmt::print(stderr, "warning: this needlesim was built without MPI; every rank runs the whole study\n");
#endif
    study::SweepReport rep;
    installStopHandlers();  // Ctrl-C: running cases stop cleanly, finished ones stay for --resume
    exitOnStopInBlockingCalls(fmt::format("; each finished case is kept: continue with needlesim sweep {} --resume", a->file));
    try {
      rep = study::runSweep(spec, opt);
    } catch (...) {
#ifdef NEEDLESIM_WITH_MPI
      if (mpi) MPI_Abort(MPI_COMM_WORLD, 2);
#endif
      throw;
    }
#ifdef NEEDLESIM_WITH_MPI
    if (mpi) {
      int failedHere = static_cast<int>(rep.failed.size()), failedAll = 0;
      MPI_Reduce(&failedHere, &failedAll, 1, MPI_INT, MPI_SUM, 0, MPI_COMM_WORLD);
      MPI_Barrier(MPI_COMM_WORLD);
      if (opt.rank == 0) {
        std::string baseYaml;
        auto cases = study::expandCases(spec, [&] {
          std::ifstream in(spec.scenario_file);
          return std::string((std::istreambuf_iterator<char>(in)), {});
        }());
        study::gatherSweep(spec, cases, rep);
      }
      MPI_Finalize();
      if (opt.rank != 0) {
        if (failedHere > 0) throw Error(fmt::format("rank {}: {} case(s) failed", opt.rank, failedHere));
        return;
      }
    }
#endif
    if (!a->quiet || !rep.failed.empty()) {
      fmt::print("study '{}': {} cases, {} run now, {} reused; results in {}/ (study.csv, report.html)\n{}", spec.name,
                 rep.cases, rep.ran, rep.reused, rep.folder.string(), rep.overview);
    }
    if (!rep.failed.empty()) {
      std::string list;
      for (int i : rep.failed) list += (list.empty() ? "" : ", ") + std::to_string(i);
      throw SolverError(fmt::format("{} case(s) did not complete: {} (see cases/case_NNNN.error.txt; the others' results "
                                    "are kept). Fix the cause and rerun with --resume to run only these.",
                                    rep.failed.size(), list));
    }
  });
}

}  // namespace needlesim::app
