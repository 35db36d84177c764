#pragma once
// Scenario -> real-time engine settings shared by realtime2d and realtime3d: the refusals of
// what their FE tissue does not model (layer toughness and K_T, one Prony series for the
// block, sliding inclusions, an inclusion friction of its own), the needle beam, the
// puncture forces (eq 3.16) and the back-end names.
#include <string>

#include "needlesim/engines/engine.hpp"
#include "needlesim/engines/realtime/needle_settings.hpp"
#include "needlesim/engines/realtime/newmark.hpp"
#include "needlesim/scenario/scenario.hpp"

namespace needlesim::engines {

[[noreturn]] void refuseRealtime(const Scenario& sc, const std::string& engine, const std::string& field,
                                 const std::string& problem, const std::string& allowed);
// Layers: no toughness, no K_T; with relaxation, one Prony series in every material.
void checkRealtimeLayers(const Scenario& sc, const std::string& engine, bool relaxation);
// Inclusions: bonded, with the friction of the layer around them, no toughness.
void checkRealtimeInclusions(const Scenario& sc, const std::string& engine);
// The needle as a clamped Euler-Bernoulli beam; a symmetric tip carries no transverse load.
realtime::NeedleConfig realtimeNeedle(const Scenario& sc, double tip_load_ratio);
// A puncture given as a depth (LayerSpec::puncture_depth): the force of eq 3.16 with (E, nu) there.
double realtimePunctureForce(const LayerSpec& L, double E, double nu, const Scenario& sc);
realtime::Backend realtimeBackend(const std::string& solver);
// The path-node coupling needs the needle within 45 deg of the entry-face normal (SolverError).
void checkRealtimeEntryAngle(const Scenario& sc, const std::string& engine);
// How a real-time engine steps (engines/step_guard.hpp): model.time_step against the path
// nodes' spacing along the depth, block.length / (nodes_depth - 1).
StepPlan realtimeStepPlan(const Scenario& sc, const std::string& engine, int nodes_depth);

// The forces of a session (layer 0's friction, cutting and puncture; per layer the same with
// the layer's E and nu from c.tissue.layers), its frame and step, from the scenario.
template <class Settings>
void setRealtimeForces(const Scenario& sc, const std::string& engine, Settings& c) {
  const auto& L0 = sc.tissue.layers.front();
  c.friction = L0.friction;
  c.cutting_force = L0.cutting_force;
  c.puncture_force = realtimePunctureForce(L0, c.tissue.material.E, c.tissue.material.nu, sc);
  for (std::size_t i = 0; i < c.tissue.layers.size(); ++i) {
    const auto& L = sc.tissue.layers[i];
    const auto& m = c.tissue.layers[i].second;
    c.layers.push_back({c.tissue.layers[i].first, L.friction, L.cutting_force, realtimePunctureForce(L, m.E, m.nu, sc)});
  }
  c.frame = needle::InsertionFrame::fromInsertion(sc.insertion);
  c.dt = sc.model.time_step;
  checkRealtimeEntryAngle(sc, engine);
}
const char* realtimeBackendName(realtime::Backend b);

}  // namespace needlesim::engines
