#pragma once
// The settings of the steering engines kinematic, energy and beam-foundation, model.steering.
// Plain structs in SI; the table in the .cpp declares each field once (key, unit, range,
// meaning; the default is the member's initial value) and reads it.
#include <string>
#include <vector>

namespace needlesim {
namespace scenario {
struct ModelSection;
}

// Bevel-tip steering engines kinematic, energy, beam-foundation (seed 002;
// docs/models/steering.md, docs/models/bevel-tip-energy.md).
struct SteeringModelSpec {
  double curvature = -1.0;        // 1/m, kinematic: curvature with the bevel fixed; < 0 = from the tip loads
  double beta_over_alpha = 0.5;   // cut angle / bevel angle (seed 002 sections 3.1, 5.2)
  double input_force = 5e-3;      // N, P_input (seed 002 section 5.2)
  std::string tip_load = "roller";  // roller (section 4 sub-step 1 reaction) | bevel-edges (eqs 24-26)
  std::string energy_frame = "path-window";  // entry | path-window (energy model trial-function frame)
  double increment = 1e-3;        // m, insertion increment / element length / path sampling
  double friction_dissipation = 0.0;  // energy: share of the input work lost to friction (Fig 23)
  double tear_length = 0.0;       // m, energy: a of eq 44; 0 = the needle radius
  double fracture_energy = 0.44;  // J/m^2, energy: G_f of eq 44 (choice 10)
  double max_step = 1e-3;         // m, energy: largest advance of one increment
  int snapshots = 5;              // needle shapes recorded along the insertion
};

namespace engines {
// model.steering: its schema rows and its reading (scenario/model_section.hpp).
const scenario::ModelSection& steeringSection();
}  // namespace engines

}  // namespace needlesim
