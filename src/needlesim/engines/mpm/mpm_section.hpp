#pragma once
// The settings of the mpm engine, model.mpm (seed 000).
// Plain structs in SI; the table in the .cpp declares each field once (key, unit, range,
// meaning; the default is the member's initial value) and reads it.
#include <string>
#include <vector>

namespace needlesim {
namespace scenario {
struct ModelSection;
}

// A tissue point whose displacement the mpm engine reports (seed 000 Fig 11).
struct MpmMarkerSpec {
  std::string name;
  double x = 0.0;  // m, depth from the entry face
  double y = 0.0;  // m, lateral from the needle path line, in the insertion plane
  double z = 0.0;  // m, from the insertion plane (mid-height of the block)
};

// 3D material point method engine (seed 000; docs/models/mpm.md).
// A measured force-depth curve (model.mpm.measured_force, seed 000 eq 35),
// read from its CSV when the scenario is read (scenario/measured_data.hpp).
struct MeasuredCurve {
  std::string path;                  // resolved against the scenario file, "" = none
  std::vector<double> depth, force;  // m, N
};

// Measured marker displacements (model.mpm.measured_markers, seed 000 eq 37):
// per marker of model.mpm.markers that the file measures, ux and uy at each depth.
struct MeasuredMarkers {
  struct Track {
    std::string name;              // as in model.mpm.markers
    std::vector<double> ux, uy;    // m, one per depth
  };
  std::string path;                // resolved against the scenario file, "" = none
  std::vector<double> depth;       // m
  std::vector<Track> markers;
};

struct MpmModelSpec {
  double grid_spacing = 0.8e-3;      // m, background grid h
  double particle_spacing = 0.4e-3;  // m
  bool bspline = true;               // quadratic B-spline (false: linear hat, the paper's)
  bool musl = true;                  // modified update-stress-last (false: USL)
  bool fbar = false;                 // anti-locking: F-bar with the cell-averaged det F
  bool cfemp = true;                 // needle contact: CFEMP particle-to-surface (eqs 22-24); false: grid (eqs 14-21)
  double cfemp_element_size = 0.0;   // m, d_e of the eq 22 gap rule (0: the exact surface, gap d_p/2)
  // The tissue parts along the needle's cut: "tip" (from the entry to where the tip reaches the cut's
  // plane), "path" (pre-cut from the entry to the insertion's deepest point) or "none" (one velocity field).
  std::string parting = "tip";
  // Where the cut runs: "axis" (the strip through the axis, each lip opened by half the needle) or
  // "edges" (the lower half of the needle's surface, which the bevel's cutting edges sweep).
  std::string cut = "axis";
  double tip_friction = 0.0;         // CFEMP: Coulomb coefficient on the tip's surface (default: the tissue's)
  double flip = 1.0;                 // FLIP fraction (1 = eq 4)
  double time_step_factor = 0.4;     // k_t, eq 26
  double mass_scaling = 1.0;         // factor on the particle masses (eq 28 discussion)
  int margin = 3;                    // grid cells beyond the block
  int threads = 0;                   // 0 = all cores
  bool cuda = false;                 // device: cpu (false) or cuda (the GPU plugin, engines/mpm/cuda)
  // Face conditions: entry (depth 0), exit, y_min, y_max, z_min, z_max; each
  // "free", "fixed", "roller" or "non-reflecting".
  std::vector<std::string> faces{"free", "fixed", "free", "free", "free", "free"};
  double field_interval = 0.5;       // s, particle fields for ParaView (0 = none)
  double marker_depth_step = 0.0;    // m, marker rows each time the tip advances this far (0 = output interval)
  std::vector<MpmMarkerSpec> markers;
  MeasuredCurve measured_force;      // CSV: depth and force
  MeasuredMarkers measured_markers;  // CSV: depth and <name>_ux, <name>_uy per marker (eq 37)
};

namespace engines {
// model.mpm: its schema rows and its reading (scenario/model_section.hpp).
const scenario::ModelSection& mpmSection();
}  // namespace engines

}  // namespace needlesim
