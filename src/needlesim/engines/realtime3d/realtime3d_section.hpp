#pragma once
// The settings of the realtime3d engine, model.realtime3d.
// Plain structs in SI; the table in the .cpp declares each field once (key, unit, range,
// meaning; the default is the member's initial value) and reads it.
#include <string>
#include <vector>

#include "needlesim/engines/realtime2d/realtime2d_section.hpp"  // MarkerSpec

namespace needlesim {
namespace scenario {
struct ModelSection;
}

// Real-time 3D FE engine (tetrahedral block, docs/models/realtime3d.md).
struct Realtime3dModelSpec {
  int nodes_depth = 41;          // nodes along the insertion axis (block.length)
  int nodes_lateral = 16;        // nodes across the width (block.width)
  int nodes_height = 16;         // nodes across the height (block.height)
  double refinement = 8.0;       // coarsest / finest lateral element size (finest on the path)
  double coupling_spacing = 1e-3;  // m, between the path points the shaft couples to
  bool lumped_mass = false;
  double rayleigh_alpha = 0.01;  // 1/s (seed 003 eq 3.8)
  double rayleigh_beta = 0.1;    // s
  double newmark_gamma = 0.5;    // eq 3.2
  double newmark_beta = 0.25;    // eq 3.3
  bool hold_sides = true;        // false: only the far face held
  std::string solver = "auto";   // auto, direct, modal, reduced
  int modes = 60;                // reduced: most kept modes
  double tip_load_ratio = -1.0;  // transverse bevel load / cutting force; < 0 = cot(bevel angle)
  double field_interval = 0.5;   // s, tissue field output interval (0 = none)
  bool relaxation = true;        // Prony terms of the material relax the tissue (QLV)
  bool follow_tip = false;       // path: follow_tip (the channel the tip cuts) or straight (the reference axis)
  double curvature = -1.0;       // 1/m, follow_tip: the channel's curvature; < 0 = as engine kinematic
  std::vector<MarkerSpec> markers;
};

namespace engines {
// model.realtime3d: its schema rows and its reading (scenario/model_section.hpp).
const scenario::ModelSection& realtime3dSection();
}  // namespace engines

}  // namespace needlesim
