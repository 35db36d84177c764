#include <algorithm>
#include <fmt/format.h>

#include "needlesim/engines/engine.hpp"
#include "needlesim/mesh/volume_mesh.hpp"
#include "needlesim/engines/explicit/explicit_engine.hpp"
#include "needlesim/engines/lumped/lumped_engine.hpp"
#include "needlesim/engines/mpm/mpm_engine.hpp"
#include "needlesim/engines/realtime2d/realtime2d_engine.hpp"
#include "needlesim/engines/realtime3d/realtime3d_engine.hpp"
#include "needlesim/engines/steering/steering_engines.hpp"

namespace needlesim {

namespace {
// A preflight from an engine's step plan: the step guards without running.
template <StepPlan (*plan)(const Scenario&)>
StepEstimate guarded(const Scenario& sc) {
  return guardSteps(sc, plan(sc));
}
}  // namespace

const std::vector<EngineInfo>& engineRegistry() {
  using namespace engines;
  static const std::vector<EngineInfo> list{
      {"lumped", "lumped insertion-force model (seed 003 section 3.2)", runLumped, false, false,
       guarded<lumpedStepPlan>},
      {"realtime2d", "real-time 2D FE tissue with a needle beam (seed 003 sections 3.1-3.5)", runRealtime2d, false,
       true, guarded<realtime2dStepPlan>, {2}},
      {"realtime3d", "real-time 3D FE tissue (tetrahedral block) with a needle beam bending in two planes",
       runRealtime3d, false, true, guarded<realtime3dStepPlan>},
      {"kinematic", "bevel-tip kinematic steering model, 3D (Webster et al. 2006)", runKinematic, false, false,
       guarded<steeringStepPlan>},
      {"energy", "bevel-tip energy-based deflection model (seed 002 section 4)", runEnergy, false, false,
       guarded<energyStepPlan>},
      {"beam-foundation", "bevel-tip needle as a beam on an elastic foundation (seed 002 future work)",
       runBeamFoundation, false, false, guarded<steeringStepPlan>},
      {"mpm", "3D material point method with a rigid needle, grid contact and friction (seed 000)", runMpm, true, true,
       guarded<mpmStepPlan>, {3}},
      {"explicit", "explicit large-deformation FE with needle contact and friction (seeds 001, 004)", runExplicit,
       false, true, guarded<explicitStepPlan>, {2, 3}},
  };
  return list;
}

const EngineInfo* findEngine(const std::string& name) {
  const auto& l = engineRegistry();
  auto it = std::find_if(l.begin(), l.end(), [&](const EngineInfo& e) { return e.name == name; });
  return it == l.end() ? nullptr : &*it;
}

const EngineInfo& engineFor(const Scenario& sc) {
  const EngineInfo* engine = findEngine(sc.model.engine);
  auto names = [](bool (*accepts)(const EngineInfo&)) {
    std::string s;
    for (const auto& e : engineRegistry())
      if (accepts(e)) s += (s.empty() ? "" : ", ") + e.name;
    return s;
  };
  auto takingGeometry = [](int dim) {
    std::string s;
    for (const auto& e : engineRegistry())
      if (std::find(e.geometry.begin(), e.geometry.end(), dim) != e.geometry.end()) s += (s.empty() ? "" : ", ") + e.name;
    return s;
  };
  if (!engine)
    throw InputError(sc.where("model.engine"), "model.engine", sc.model.engine,
                     "is reserved for an engine that this build does not have yet",
                     names([](const EngineInfo&) { return true; }));
  if (!sc.tissue.inclusions.empty() && !engine->inclusions)
    throw InputError(sc.where("tissue.inclusions"), "tissue.inclusions", sc.tissue.inclusions.front().name,
                     "engine " + engine->name + " does not model bodies embedded in the tissue",
                     "no inclusions, or engine " + names([](const EngineInfo& e) { return e.inclusions; }));
  if (const auto& g = sc.tissue.geometry;
      g && std::find(engine->geometry.begin(), engine->geometry.end(), g->mesh->dim) == engine->geometry.end())
    throw InputError(sc.where("tissue.geometry"), "tissue.geometry", g->file,
                     fmt::format("engine {} does not take an imported {}D geometry", engine->name, g->mesh->dim),
                     "tissue.block, or an engine that takes it: " + takingGeometry(g->mesh->dim));
  return *engine;
}

StepEstimate preflight(const Scenario& sc) { return engineFor(sc).preflight(sc); }

}  // namespace needlesim
