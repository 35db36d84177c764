// The engines built into this binary, each registered by one entry: how it runs, its model
// section, the fields it uses; and the refusals of what an engine does not model.
#include <algorithm>
#include <map>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "needlesim/engines/engine.hpp"
#include "needlesim/mesh/volume_mesh.hpp"
#include "needlesim/engines/explicit/explicit_engine.hpp"
#include "needlesim/engines/lumped/lumped_engine.hpp"
#include "needlesim/engines/lumped/lumped_session.hpp"
#include "needlesim/engines/mpm/mpm_engine.hpp"
#include "needlesim/engines/realtime2d/realtime2d_engine.hpp"
#include "needlesim/engines/realtime2d/steppable_session.hpp"
#include "needlesim/engines/realtime3d/realtime3d_engine.hpp"
#include "needlesim/engines/realtime3d/steppable_session.hpp"
#include "needlesim/engines/steering/steering_engines.hpp"
#include "needlesim/scenario/model_section.hpp"

namespace needlesim {

namespace {
// The steering engines' tissue: K_T and G_c (seed 002); their friction is Coulomb's.
const std::vector<std::string> kSteeringTissue{"interaction.K_T", "interaction.toughness"};
// What the lumped force model uses of a layer besides its friction (seed 003 eqs 3.16, 3.24).
const std::vector<std::string> kLumpedForces{"puncture.force", "puncture.depth", "cutting.force"};

// A preflight from an engine's step plan: the step guards without running.
template <StepPlan (*plan)(const Scenario&)>
StepEstimate guarded(const Scenario& sc) {
  return guardSteps(sc, plan(sc));
}

std::vector<std::string> with(std::vector<std::string> a, const std::vector<std::string>& b) {
  a.insert(a.end(), b.begin(), b.end());
  return a;
}
}  // namespace

const std::vector<std::string>& frictionFields(FrictionLaw law) {
  static const std::vector<std::string> karnopp{"friction.C_p", "friction.b_p", "friction.C_n",        "friction.b_n",
                                                "friction.D_p", "friction.D_n", "friction.static_band"};
  static const std::vector<std::string> coulomb{"friction.coefficient", "inclusions.friction"};
  static const std::vector<std::string> none;
  return law == FrictionLaw::Karnopp ? karnopp : law == FrictionLaw::Coulomb ? coulomb : none;
}

const char* frictionLawName(FrictionLaw law) {
  return law == FrictionLaw::Karnopp ? "Karnopp" : law == FrictionLaw::Coulomb ? "Coulomb" : "none";
}

bool EngineInfo::usesField(const std::string& field) const {
  const auto& law = frictionFields(friction);
  return std::find(uses.begin(), uses.end(), field) != uses.end() ||
         std::find(law.begin(), law.end(), field) != law.end();
}

const std::vector<std::string>& engineDependentFields() {
  static const std::vector<std::string> all =
      with(with(kLumpedForces, frictionFields(FrictionLaw::Karnopp)),
           with(frictionFields(FrictionLaw::Coulomb), {"interaction.K_T", "interaction.toughness", "material.prony",
                                                       "inclusions.toughness", "inclusions.interface_friction"}));
  return all;
}

// One line per engine: name, summary, run, checkpoints, inclusions, preflight, imported geometry
// dimensions, its model section, its friction law, the other fields it uses, how a caller steps it, and
// whether it runs on OpenMP threads.
const std::vector<EngineInfo>& engineRegistry() {
  using namespace engines;
  using enum FrictionLaw;
  static const std::vector<EngineInfo> list{
      {"lumped", "lumped insertion-force model (seed 003 section 3.2)", runLumped, false, false,
       guarded<lumpedStepPlan>, {}, lumpedSection, Karnopp, kLumpedForces, openLumpedSession},
      {"realtime2d", "real-time 2D FE tissue with a needle beam (seed 003 sections 3.1-3.5)", runRealtime2d, false,
       true, guarded<realtime2dStepPlan>, {2}, realtime2dSection, Karnopp, with(kLumpedForces, {"material.prony"}),
       openRealtime2dSession},
      {"realtime3d", "real-time 3D FE tissue (tetrahedral block or imported tet mesh) with a needle beam bending in two planes",
       runRealtime3d, false, true, guarded<realtime3dStepPlan>, {3}, realtime3dSection, Karnopp,
       with(kLumpedForces, {"material.prony"}), openRealtime3dSession},
      {"kinematic", "bevel-tip kinematic steering model, 3D (Webster et al. 2006)", runKinematic, false, false,
       guarded<steeringStepPlan>, {}, steeringSection, Coulomb, kSteeringTissue},
      {"energy", "bevel-tip energy-based deflection model (seed 002 section 4)", runEnergy, false, false,
       guarded<energyStepPlan>, {}, steeringSection, Coulomb, kSteeringTissue},
      {"beam-foundation", "bevel-tip needle as a beam on an elastic foundation (seed 002 future work)",
       runBeamFoundation, false, false, guarded<steeringStepPlan>, {}, steeringSection, Coulomb, kSteeringTissue},
      {"mpm", "3D material point method with a rigid needle, its surface contact (CFEMP) and friction (seed 000)", runMpm, true, true,
       guarded<mpmStepPlan>, {3}, mpmSection, Coulomb, {"inclusions.interface_friction"}, nullptr, true},
      {"explicit", "explicit large-deformation FE with needle contact and friction (seeds 001, 004)", runExplicit,
       false, true, guarded<explicitStepPlan>, {2, 3}, explicitSection, Coulomb,
       {"interaction.toughness", "inclusions.toughness", "material.prony", "model.steering",
        "interaction.K_T"},  // the last two: cohesive.path steering
       nullptr, true},
  };
  return list;
}

namespace {
// "tissue.layers[0].material.prony[1].g" -> the field "material.prony" given at
// "tissue.layers[0].material.prony"; "tissue.friction.C_p" -> "friction.C_p".
std::pair<std::string, std::string> dependentField(const std::string& path) {
  std::string bare;
  for (std::size_t i = 0; i < path.size(); ++i) {
    if (path[i] == '[') i = path.find(']', i);
    else bare += path[i];
  }
  if (const auto at = path.find(".prony"); at != std::string::npos) return {"material.prony", path.substr(0, at + 6)};
  const auto last = bare.rfind('.');
  const auto before = last == std::string::npos ? std::string::npos : bare.rfind('.', last - 1);
  return {before == std::string::npos ? bare : bare.substr(before + 1), path};
}

// "model.mpm.faces.exit" -> "model.mpm"
std::string modelSectionOf(const std::string& path) {
  if (!path.starts_with("model.")) return {};
  const auto end = path.find_first_of(".[", 6);
  return end == std::string::npos ? std::string() : path.substr(0, end);
}
}  // namespace

std::vector<std::string> unusedFieldNotes(const EngineInfo& engine, const Scenario& sc) {
  if (sc.from_record) return {};  // a summary.json writes every field; its run noted what was given
  const auto& dependent = engineDependentFields();
  const auto used = [&](const std::string& f) { return engine.usesField(f); };
  std::map<std::string, std::vector<std::string>> unused;  // field -> where given
  for (const auto& [path, at] : sc.given_at) {
    auto [field, where] = dependentField(path);
    const std::string section = modelSectionOf(path);
    const bool own = engine.section && section == "model." + engine.section().key;
    if (!section.empty() && !own && !used(section) && section != "model.engine" && section != "model.time_step")
      field = where = section;
    else if (std::find(dependent.begin(), dependent.end(), field) == dependent.end() || used(field))
      continue;
    auto& list = unused[field];
    if (std::find(list.begin(), list.end(), where) == list.end()) list.push_back(where);
  }
  std::vector<std::string> notes;
  for (const auto& [field, where] : unused)
    notes.push_back(fmt::format("{} given but not used by engine {}{} (docs/scenario-format.md, \"Engines\")",
                                fmt::format("{}", fmt::join(where, ", ")), engine.name,
                                where.size() == 1 && where[0] == field ? "" : " (" + field + ")"));
  return notes;
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

namespace scenario {

const std::vector<const ModelSection*>& modelSections() {
  static const std::vector<const ModelSection*> list = [] {
    std::vector<const ModelSection*> out;
    for (const auto& e : engineRegistry())
      if (e.section && std::find(out.begin(), out.end(), &e.section()) == out.end()) out.push_back(&e.section());
    return out;
  }();
  return list;
}

std::vector<std::pair<std::string, std::string>> engineNames() {
  std::vector<std::pair<std::string, std::string>> out;
  for (const auto& e : engineRegistry())
    out.emplace_back(e.name, fmt::format("{} (friction: {})", e.summary, frictionLawName(e.friction)));
  return out;
}

}  // namespace scenario

}  // namespace needlesim
