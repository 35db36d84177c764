#include "needlesim/engines/run_scenario.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <optional>
#include <thread>

#include "needlesim/core/error.hpp"
#include "needlesim/results/checkpoint.hpp"

namespace needlesim {

namespace {

// One engine's `threads` beyond the machine's hardware threads, capped with a warning
// (more threads than cores only slow a run down, and thousands make OpenMP fail).
void capThreads(int& threads, const std::string& field, int cores, ResultSink& sink) {
  if (threads <= cores) return;
  sink.warning(fmt::format("{}: {} is more than this machine's {} hardware threads; {} are used", field, threads, cores,
                           cores));
  threads = cores;
}

// The scenario with model.mpm.threads and model.explicit.threads capped (capThreads);
// empty when nothing needs a cap.
std::optional<Scenario> withThreadsCapped(const Scenario& sc, ResultSink& sink) {
  const int cores = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  if (sc.model.mpm.threads <= cores && sc.model.explicit_fe.threads <= cores) return std::nullopt;
  std::optional<Scenario> capped(sc);
  if (sc.model.engine == "mpm") capThreads(capped->model.mpm.threads, "model.mpm.threads", cores, sink);
  if (sc.model.engine == "explicit") capThreads(capped->model.explicit_fe.threads, "model.explicit.threads", cores, sink);
  capped->model.mpm.threads = std::min(capped->model.mpm.threads, cores);
  capped->model.explicit_fe.threads = std::min(capped->model.explicit_fe.threads, cores);
  return capped;
}

// Runs the engine into `folder` and commits it (as "stopped" with the reason
// when the solver stops); returns the wall time.
double runAndCommit(const EngineInfo& engine, const Scenario& sc, io::ResultsFolder& folder, bool overwrite,
                    const RunOptions& options) {
  const auto t0 = std::chrono::steady_clock::now();
  auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(); };
  try {
    const std::optional<Scenario> capped = withThreadsCapped(sc, folder);
    for (const auto& note : unusedFieldNotes(engine, sc)) folder.note(note);
    engine.run(capped ? *capped : sc, folder, options);
  } catch (const SolverError& e) {
    // Keep what was computed up to the failure, marked as stopped, then report.
    folder.commit(overwrite, elapsed(), e.what());
    if (options.checkpoint) options.checkpoint->remove();  // resuming would stop at the same place
    throw SolverError(std::string(e.what()) + " (results up to this point are in " + folder.target().string() + ")");
  }
  const double wall = elapsed();
  folder.commit(overwrite, wall);
  if (options.checkpoint) options.checkpoint->remove();
  return wall;
}
}  // namespace

RunOutcome runScenario(const Scenario& sc, const std::filesystem::path& target, bool overwrite,
                       const RunOptions& options) {
  const EngineInfo& engine = engineFor(sc);
  io::ResultsFolder folder(sc, target, options.printWarnings);
  try {
    const double wall = runAndCommit(engine, sc, folder, overwrite, options);
    return RunOutcome{folder.target(), folder.results(), folder.tables(), wall, folder.files()};
  } catch (const InputError&) {
    throw;
  } catch (const SolverError&) {
    throw;
  } catch (const RunInterrupted&) {
    throw;
  } catch (const Error& e) {  // a file that could not be written, a set-up that failed: nothing is committed
    throw Error(std::string(e.what()) + "; the run is not committed (no results folder " + folder.target().string() +
                ")");
  }
}

}  // namespace needlesim

#include "needlesim/engines/memory_sink.hpp"

namespace needlesim {

MemorySink runInMemory(const Scenario& sc, const RunOptions& options) {
  const EngineInfo* engine = &engineFor(sc);
  MemorySink sink;
  const std::optional<Scenario> capped = withThreadsCapped(sc, sink);
  for (const auto& note : unusedFieldNotes(*engine, sc)) sink.note(note);
  engine->run(capped ? *capped : sc, sink, options);
  return sink;
}

}  // namespace needlesim
