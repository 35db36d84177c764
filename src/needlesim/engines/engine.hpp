#pragma once
// What an engine is: a function from a typed Scenario to results reported
// through a ResultSink. Engines never parse YAML and never write files.
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "needlesim/core/error.hpp"
#include "needlesim/core/progress.hpp"  // RunInterrupted
#include "needlesim/engines/step_guard.hpp"
#include "needlesim/results/result_sink.hpp"
#include "needlesim/scenario/scenario.hpp"

namespace needlesim {
namespace scenario {
struct ModelSection;
}
namespace io {
class Checkpoint;
}
namespace engines {
class SteppableSession;
}

struct RunOptions {
  bool progress = true;  // show progress on a terminal
  // Checkpoints (results/checkpoint.hpp): where to write them, how often, and
  // whether to resume; nullptr = none (sweeps, in-memory runs). Engines that
  // do not support them ignore it (only mpm writes checkpoints so far).
  io::Checkpoint* checkpoint = nullptr;
  // Test hook: the engine stops after this many steps (counted from the start
  // of the run, not of the resumed part) by throwing RunInterrupted, as if the
  // process had been killed there (0 = off). A stop request (Ctrl-C, SIGTERM;
  // core/progress.hpp) throws RunInterrupted too, after a final checkpoint.
  long long stopAfterSteps = 0;
  // Print each warning on stderr as it is raised (results folders; --quiet: off).
  bool printWarnings = true;
};

using EngineFn = std::function<void(const Scenario&, ResultSink&, const RunOptions&)>;
// The engine's step guards and its estimate (engines/step_guard.hpp) without
// running it: what `needlesim check` applies. Throws InputError as run would.
using PreflightFn = std::function<StepEstimate(const Scenario&)>;
// Opens a session a caller steps (engines/session.hpp): the C++ API, Python and `serve`.
using SessionOpenFn = std::unique_ptr<engines::SteppableSession> (*)(const Scenario&);

struct EngineInfo {
  std::string name;
  std::string summary;
  EngineFn run;
  bool checkpoints = false;  // writes checkpoints and can resume (RunOptions::checkpoint)
  bool inclusions = false;   // models tissue.inclusions (else a scenario with them is refused)
  PreflightFn preflight;
  std::vector<int> geometry = {};  // dimensions of an imported tissue.geometry it takes (else refused)
  // Its settings model.<key>, declared beside it (engines/<engine>/<engine>_section.cpp);
  // engines that share settings name the same section.
  const scenario::ModelSection& (*section)() = nullptr;
  // The law it applies along the shaft (contact/friction_spec.hpp): it uses that law's fields of
  // the friction section (frictionFields) and no other's.
  FrictionLaw friction = FrictionLaw::None;
  // The other fields of the needle-tissue interaction it uses (engineDependentFields()) and any
  // other engine's section it reads ("model.steering"); each other one the scenario gives gets a note.
  std::vector<std::string> uses = {};
  // How a caller steps it (engines/session.hpp), or nullptr: it runs only as a whole.
  SessionOpenFn open = nullptr;
  // Whether its steps run on OpenMP threads (the run command chooses how they wait: apps/needlesim/openmp_wait.cpp).
  bool openmp = false;
  // Whether it uses `field` (as engineDependentFields() names it, or "model.<key>").
  bool usesField(const std::string& field) const;
};

// The scenario fields of a friction law: Karnopp's per-length coefficients (friction.C_p ...
// friction.static_band), Coulomb's coefficients (friction.coefficient, inclusions.friction).
const std::vector<std::string>& frictionFields(FrictionLaw law);
// "Karnopp", "Coulomb" or "none".
const char* frictionLawName(FrictionLaw law);

// The scenario fields whose use depends on the engine (puncture, cutting, friction,
// interaction, Prony terms, inclusion contact), as "<section>.<key>" (e.g. friction.C_p).
const std::vector<std::string>& engineDependentFields();
// One note per field the scenario gives that `engine` does not use (a field of
// engineDependentFields() outside engine.uses, or another engine's model section), naming where
// it is given.
std::vector<std::string> unusedFieldNotes(const EngineInfo& engine, const Scenario& scenario);

// All engines built into this binary (engines/registry.cpp).
const std::vector<EngineInfo>& engineRegistry();
const EngineInfo* findEngine(const std::string& name);
// The scenario's engine, after checking that it models everything the scenario
// asks for: InputError (naming the file, the field and the engines that can) for an
// unknown engine or a tissue feature it does not model (inclusions, an imported geometry). Used by run and check.
const EngineInfo& engineFor(const Scenario& scenario);
// engineFor, then its preflight: the step guards and the run's estimate.
StepEstimate preflight(const Scenario& scenario);

}  // namespace needlesim
