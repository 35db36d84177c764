#include "needlesim/engines/run_scenario.hpp"

#include <chrono>

#include "needlesim/core/error.hpp"
#include "needlesim/io/checkpoint.hpp"

namespace needlesim {

namespace {
// Runs the engine into `folder` and commits it (as "stopped" with the reason
// when the solver stops); returns the wall time.
double runAndCommit(const EngineInfo& engine, const Scenario& sc, io::ResultsFolder& folder, bool overwrite,
                    const RunOptions& options) {
  const auto t0 = std::chrono::steady_clock::now();
  auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(); };
  try {
    engine.run(sc, folder, options);
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
  engine->run(sc, sink, options);
  return sink;
}

}  // namespace needlesim
