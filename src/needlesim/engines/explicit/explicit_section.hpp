#pragma once
// The settings of the explicit engine, model.explicit (seeds 001, 004).
// Plain structs in SI; the table in the .cpp declares each field once (key, unit, range,
// meaning; the default is the member's initial value) and reads it.
#include <string>
#include <vector>

#include "needlesim/engines/realtime2d/realtime2d_section.hpp"  // MarkerSpec, shared by the markers

namespace needlesim {
namespace scenario {
struct ModelSection;
}

// Explicit large-deformation FE (engines/explicit, docs/models/explicit.md).
// model.explicit.cohesive (docs/models/cohesive.md): bilinear cohesive law on the
// 2D pre-cut seam instead of node release. K: `stiffness`, or E / T0 from
// `constitutive_thickness`, or 10 E'/h (h = element_size); t_c: `strength`, or
// 2 G_c / delta_c from `critical_separation`; G_c: `fracture_energy`, or each
// layer's interaction.toughness.
struct ExplicitCohesiveSpec {
  bool enable = false;
  double stiffness = 0.0;               // Pa/m (0 = from constitutive_thickness or 10 E'/h)
  double constitutive_thickness = 0.0;  // m, K = E / T0 (seed 004's T0)
  double strength = 0.0;                // Pa, t_c (0 = 2 G_c / critical_separation)
  double critical_separation = 0.0;     // m, delta_c (seed 004)
  double fracture_energy = 0.0;         // J/m^2 (0 = layer's interaction.toughness)
  double mode_ii_ratio = 1.0;           // G_IIc / G_Ic (shear strength = t_c)
  // crack path = the needle axis path (docs/models/cohesive.md "Crack path"): straight, points
  // (path_points: depth x, lateral y from the straight line through the entry point), arc
  // (path_radius, + curving towards +y) or steering (the steering model's predicted tip path)
  std::string path = "straight";
  struct PathPoint {
    double x = 0.0, y = 0.0;  // m
  };
  std::vector<PathPoint> path_points;
  double path_radius = 0.0;  // m, signed
  std::string seam = "plane";           // plane | sleeve (3D cylinder around the axis, explicit/mesh_sleeve.hpp)
  double sleeve_radius = 0.0;           // m, sleeve seam radius (0 = the needle wall's mid radius)
};

struct ExplicitModelSpec {
  int dimension = 2;                 // 2 (plane strain) or 3
  std::string element;               // quad4, tri3, hex8, tet4; "" = quad4 (2D) / hex8 (3D)
  double element_size = 0.5e-3;      // m, core element size around the needle path (seed 001: 0.25 mm)
  double max_element_size = 3e-3;    // m, at the block boundary (seed 001: 3 mm)
  double core_width = 6e-3;          // m, refined zone around the path (seed 001: 6 mm)
  double grading = 1.25;             // growth ratio of neighbouring elements outside the core
  double mass_scaling = 1.0;         // factor on the density
  double target_time_step = 0.0;     // s, mass-scale elements below it (0 = off)
  double cfl = 0.9;
  double bulk_viscosity_linear = 0.06;
  double bulk_viscosity_quadratic = 1.2;
  double hourglass = 1.0;
  double damping = 0.0;              // 1/s, mass-proportional
  double contact_penalty = 10.0;     // k = penalty m / dt^2 (explicit/contact_normal.cpp)
  double tip_friction = 0.0;         // Coulomb coefficient on the tip surface (seed 001: 0)
  bool fixed_contact_stiffness = false;  // one k from the first contact step (default: k per contact episode, docs/models/explicit.md)
  std::string needle_model = "rigid";  // rigid or beam (explicit/deformable_needle.hpp)
  bool pre_cut = true;               // node-release seam along the needle path
  ExplicitCohesiveSpec cohesive;     // cohesive law on the seam instead of node release (2D, 3D hex8)
  double field_interval = 0.0;       // s, ParaView fields (0 = 20 frames over the run)
  int threads = 0;                   // OpenMP threads (0 = all)
  std::vector<MarkerSpec> markers;   // tissue points whose displacement is reported (marker_location.hpp)
  std::string tip = "contact";       // contact: the needle cuts in; bonded: seed 004 Fig 13a (bonded_tip.hpp)
};

namespace engines {
// model.explicit: its schema rows and its reading (scenario/model_section.hpp).
const scenario::ModelSection& explicitSection();
}  // namespace engines

}  // namespace needlesim
