#pragma once
// The settings of the realtime2d engine, model.realtime2d, and the markers of the real-time engines.
// Plain structs in SI; the table in the .cpp declares each field once (key, unit, range,
// meaning; the default is the member's initial value) and reads it.
#include <string>
#include <vector>

namespace needlesim {
struct Scenario;
namespace scenario {
struct ModelSection;
class Section;
struct FieldDoc;
}

// A point of the tissue whose displacement is reported (realtime2d, realtime3d engines).
struct MarkerSpec {
  std::string name;
  double x = 0.0;  // m, depth from the entry face
  double y = 0.0;  // m, lateral from the needle path line through the entry point
  double z = 0.0;  // m, from the insertion plane (mid-height of the block; realtime3d only)
};

// Real-time 2D FE engine (seed 003 sections 3.1-3.5; docs/models/realtime2d.md).
struct Realtime2dModelSpec {
  double element_size = 0.0;   // m, 0 = use the node counts
  int nodes_depth = 21;        // nodes along the insertion axis
  int nodes_lateral = 31;      // nodes across it
  double refinement = 1.0;     // coarsest / finest lateral element size (finest on the path)
  bool plane_strain = true;    // false = plane stress
  double thickness = 1e-3;     // m, out-of-plane extent of the slab
  bool lumped_mass = false;
  double rayleigh_alpha = 0.01;  // 1/s (seed 003 eq 3.8)
  double rayleigh_beta = 0.1;    // s
  double newmark_gamma = 0.5;    // eq 3.2
  double newmark_beta = 0.25;    // eq 3.3
  bool spring_boundary = false;  // false: sides held; true: spring supports
  double spring_stiffness = 0.0; // N/m^3
  std::string solver = "auto";   // auto, direct, modal, reduced
  double tip_load_ratio = -1.0;  // transverse bevel load / cutting force; < 0 = cot(bevel angle)
  double field_interval = 0.5;   // s, tissue field output interval (0 = none)
  std::vector<MarkerSpec> markers;
  bool relaxation = true;          // Prony terms of the material relax the tissue (QLV)
  double stiffening_factor = 1.0;  // E factor of the elements around the path (seed 003 section 3.5 item 4)
  double stiffening_radius = 0.0;  // m, half-width of that zone
};

namespace engines {
// The markers of a real-time engine's section (markers: a list of `marker`, or of `marker3d`
// when with_z): inside the block, each name once.
std::vector<MarkerSpec> readRealtimeMarkers(scenario::Section& engine, const Scenario& sc, bool with_z);
// The schema rows of those markers: `marker` (name, x, y) or, with_z, `marker3d` (and z).
std::vector<scenario::FieldDoc> realtimeMarkerDocs(bool with_z, const std::string& y_help);
// The real-time engines' path-node coupling needs the needle within 45 deg of the entry-face
// normal: InputError at insertion.entry_angle otherwise.
void refuseShallowEntry(const Scenario& sc, const std::string& engine);
// model.realtime2d: its schema rows and its reading (scenario/model_section.hpp).
const scenario::ModelSection& realtime2dSection();
}  // namespace engines

}  // namespace needlesim
