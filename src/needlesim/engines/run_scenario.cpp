#include "needlesim/engines/run_scenario.hpp"

#include <chrono>

#include "needlesim/core/error.hpp"
#include "needlesim/io/checkpoint.hpp"

namespace needlesim {

RunOutcome runScenario(const Scenario& sc, const std::filesystem::path& target, bool overwrite,
                       const RunOptions& options) {
  const EngineInfo* engine = &engineFor(sc);
  io::ResultsFolder folder(sc, target);
  auto t0 = std::chrono::steady_clock::now();
  auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(); };
  try {
    engine->run(sc, folder, options);
  } catch (const SolverError& e) {
    // Keep what was computed up to the failure, marked as stopped, then report.
    folder.commit(overwrite, elapsed(), e.what());
    if (options.checkpoint) options.checkpoint->remove();  // resuming would stop at the same place
    throw SolverError(std::string(e.what()) + " (results up to this point are in " + target.string() + ")");
  }
  const double wall = elapsed();
  folder.commit(overwrite, wall);
  if (options.checkpoint) options.checkpoint->remove();
  return RunOutcome{target, folder.results(), wall};
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
