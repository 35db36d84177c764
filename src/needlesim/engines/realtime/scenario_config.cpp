#include "needlesim/engines/realtime/scenario_config.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "needlesim/core/error.hpp"
#include "needlesim/forces/stiffness.hpp"

namespace needlesim::engines {

void refuseRealtime(const Scenario& sc, const std::string& engine, const std::string& field,
                    const std::string& problem, const std::string& allowed) {
  throw InputError(sc.where(field), field, "", engine + ": " + problem, allowed);
}

namespace {
bool sameProny(const std::vector<materials::PronyTerm>& a, const std::vector<materials::PronyTerm>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (a[i].g != b[i].g || a[i].tau != b[i].tau) return false;
  return true;
}

// One relaxation function for the whole block: every back-end relaxes K as a whole
// (K G(t), the modal and reduced ones with one history per mode of K), so Prony terms
// that differ between materials would couple the modes.
void checkOneRelaxation(const Scenario& sc, const std::string& engine) {
  const auto& p0 = sc.tissue.layers.front().material.prony;
  const std::string why = "differs from layer 0's; the " + engine +
                          " back-ends relax the whole stiffness K with one Prony series "
                          "(the modal and reduced ones keep one relaxation history per mode of K)";
  const std::string allowed = "the Prony terms of layer 0 in every material, or model." + engine + ".relaxation: off";
  for (std::size_t i = 1; i < sc.tissue.layers.size(); ++i)
    if (!sameProny(sc.tissue.layers[i].material.prony, p0))
      refuseRealtime(sc, engine, fmt::format("tissue.layers[{}].material.prony", i), why, allowed);
  for (std::size_t i = 0; i < sc.tissue.inclusions.size(); ++i)
    if (!sameProny(sc.tissue.inclusions[i].material.prony, p0))
      refuseRealtime(sc, engine, fmt::format("tissue.inclusions[{}].material.prony", i), why, allowed);
}
}  // namespace

void checkRealtimeLayers(const Scenario& sc, const std::string& engine, bool relaxation) {
  for (std::size_t i = 0; i < sc.tissue.layers.size(); ++i) {
    const auto& L = sc.tissue.layers[i];
    if (L.toughness != 0.0)
      refuseRealtime(sc, engine, fmt::format("tissue.layers[{}].interaction.toughness", i),
                     "the tissue is cut by the constant force of eq 3.24 (cutting.force); a rupture toughness is not "
                     "modelled",
                     "no toughness (an engine with a cohesive model uses it)");
    if (L.interaction_stiffness != 0.0)
      refuseRealtime(sc, engine, fmt::format("tissue.layers[{}].interaction.K_T", i),
                     "the needle-tissue interaction is the FE coupling on the path nodes; K_T is not used",
                     "no K_T (the steering engines use it)");
  }
  if (relaxation) checkOneRelaxation(sc, engine);
}

// Bonded inclusions only; inside one the shaft meets the layer's Karnopp friction and cutting.
void checkRealtimeInclusions(const Scenario& sc, const std::string& engine) {
  for (std::size_t i = 0; i < sc.tissue.inclusions.size(); ++i) {
    const auto& I = sc.tissue.inclusions[i];
    const auto& around = sc.tissue.layers[sc.tissue.layerAt(I.x)];
    if (I.sliding)
      refuseRealtime(sc, engine, fmt::format("tissue.inclusions[{}].interface", i),
                     "a sliding inclusion (a separate body in contact) is not modelled: the mesh is one body",
                     "interface: bonded");
    if (I.friction_coefficient != around.friction.coefficient)
      refuseRealtime(sc, engine, fmt::format("tissue.inclusions[{}].friction", i),
                     "the shaft friction is the Karnopp law of the layer around it (eq 3.23); a Coulomb coefficient of "
                     "the inclusion's own is not modelled",
                     "the layer's friction (leave it out)");
    if (I.toughness != 0.0)
      refuseRealtime(sc, engine, fmt::format("tissue.inclusions[{}].toughness", i),
                     "the tissue is cut by the constant force of eq 3.24; a rupture toughness is not modelled",
                     "no toughness");
  }
}

realtime::NeedleConfig realtimeNeedle(const Scenario& sc, double tip_load_ratio) {
  const auto& nd = sc.needle;
  realtime::NeedleConfig n;
  n.length = nd.length;
  n.EI = nd.youngs_modulus * std::numbers::pi / 64.0 * (std::pow(nd.outer_diameter, 4) - std::pow(nd.inner_diameter, 4));
  n.bevel_angle = nd.bevel_angle;
  // A symmetric (conical, blunt) tip carries no transverse load.
  n.tip_load_ratio = nd.tip == TipType::Bevel ? tip_load_ratio : 0.0;
  return n;
}

double realtimePunctureForce(const LayerSpec& L, double E, double nu, const Scenario& sc) {
  if (!(L.puncture_depth > 0.0)) return L.puncture_force;
  const forces::StiffnessLaw law{E, nu, sc.needle.bevel_angle, sc.insertion.entry_angle};
  return law.force(L.puncture_depth);
}

realtime::Backend realtimeBackend(const std::string& solver) {
  using realtime::Backend;
  return solver == "direct" ? Backend::Direct
         : solver == "modal" ? Backend::Modal
         : solver == "reduced" ? Backend::Reduced
                               : Backend::Auto;
}

const char* realtimeBackendName(realtime::Backend b) {
  switch (b) {
    case realtime::Backend::Direct: return "direct";
    case realtime::Backend::Modal: return "modal";
    case realtime::Backend::Reduced: return "reduced";
    default: return "auto";
  }
}

void checkRealtimeEntryAngle(const Scenario& sc, const std::string& engine) {
  if (sc.insertion.entry_angle < 0.25 * std::numbers::pi - 1e-12)
    throw SolverError(fmt::format("{}: entry angle {:g} deg is below the 45 deg the path-node coupling "
                                  "supports (the needle axis must be within 45 deg of the entry-face normal)",
                                  engine, sc.insertion.entry_angle * 180.0 / std::numbers::pi));
}

StepPlan realtimeStepPlan(const Scenario& sc, const std::string& engine, int nodes_depth) {
  StepPlan p = fixedStepPlan(sc, engine);
  p.spacing = sc.tissue.length / std::max(1, nodes_depth - 1);
  p.spacingName = "the node spacing along the depth (block.length / (model." + engine + ".nodes_depth - 1))";
  return p;
}

}  // namespace needlesim::engines
