#pragma once
// Scenario -> real-time engine settings shared by realtime2d and realtime3d: the refusals of
// what their FE tissue does not model (layer toughness and K_T, one Prony series for the
// block, sliding inclusions, an inclusion friction of its own), the needle beam, the
// puncture forces (eq 3.16) and the back-end names.
#include <string>

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
// The reader marks a puncture depth with a negative value: converted by eq 3.16 with (E, nu).
double realtimePunctureForce(const LayerSpec& L, double E, double nu, const Scenario& sc);
realtime::Backend realtimeBackend(const std::string& solver);
const char* realtimeBackendName(realtime::Backend b);

}  // namespace needlesim::engines
