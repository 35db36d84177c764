#pragma once
// The typed scenario every engine receives: plain structs in SI units.
// Engines never parse YAML; scenario/reader.cpp builds this from a file.
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "needlesim/core/error.hpp"
#include "needlesim/core/units.hpp"
#include "needlesim/materials/material_spec.hpp"

namespace needlesim {

namespace mesh {
struct VolumeMesh;  // mesh/volume_mesh.hpp
}

// Modified Karnopp friction along the shaft, per unit length in contact
// (seed 003 eq 3.23 with the per-length coefficients of eq 5.1).
struct FrictionSpec {
  double C_p = 0.0;          // N/m, dynamic friction, insertion
  double b_p = 0.0;          // N s/m^2, damping, insertion
  double C_n = 0.0;          // N/m, dynamic friction, retraction (magnitude)
  double b_n = 0.0;          // N s/m^2, damping, retraction
  double D_p = 0.0;          // N/m, static friction limit, positive direction
  double D_n = 0.0;          // N/m, static friction limit, negative direction (magnitude)
  double static_band = 0.0;  // m/s, Delta v: |v| < Delta v/2 counts as sticking
  double coefficient = 0.0;  // Coulomb coefficient for contact engines (seed 001: 0.3)
};

struct LayerSpec {
  std::string name;
  double thickness = 0.0;            // m, along the surface normal
  materials::MaterialSpec material;  // constitutive law
  double puncture_force = 0.0;       // N, threshold of the pre-puncture stiffness force
  double cutting_force = 0.0;        // N, constant cutting force (seed 003 eq 3.24)
  FrictionSpec friction;
  double interaction_stiffness = 0.0;  // N/m^2, K_T (seed 002 eq 13); 0 = not given
  double toughness = 0.0;              // J/m^2, rupture toughness G_c; 0 = not given
};

// A body embedded in the block (a tumour to target, a vessel to avoid), bonded to
// the tissue around it or sliding against it as a separate body. Position in the tissue frame (needle/insertion_frame.hpp):
// depth x from the entry face, y across the width from the block's centre line,
// z across the height from the block's mid-plane.
struct InclusionSpec {
  // cylinder: axis along z through the whole height; mesh: a group of tissue.geometry (its elements
  // are the inclusion; x, y, z is their centroid and radius the radius of a sphere of their volume)
  enum class Shape { Sphere, Cylinder, Mesh };
  std::string name;
  Shape shape = Shape::Sphere;
  double x = 0.0, y = 0.0, z = 0.0;  // m, centre
  double radius = 0.0;               // m
  materials::MaterialSpec material;
  double friction_coefficient = 0.0;  // Coulomb coefficient of needle contact inside it
  double toughness = 0.0;             // J/m^2, 0 = not given
  bool target = false;                // the needle aims at it: its displacement is the targeting error
  bool sliding = false;               // separate body in contact with the tissue (false: bonded)
  double interface_friction = 0.0;    // Coulomb coefficient between a sliding inclusion and the tissue
  // Whether the tissue-frame point (x, y, z) lies inside it (a Mesh inclusion: never; its
  // elements carry its region, ImportedGeometry::region).
  bool contains(double px, double py, double pz) const;
};

// A tissue geometry imported from a file (tissue.geometry: a Gmsh mesh or script, or closed
// surfaces meshed by Gmsh), scaled by its unit and placed in the tissue frame by the scenario
// reader (scenario/tissue_geometry.hpp). Engines take the mesh and the region of each element
// from here; they never read the file.
struct ImportedGeometry {
  std::string file;                        // as the scenario names it (several surfaces: joined by ", ")
  std::shared_ptr<const mesh::VolumeMesh> mesh;  // placed: tissue frame, metres
  std::vector<int> region;                 // per element: layer index, or layers.size() + inclusion index
  double lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};  // m, bounding box of the placed mesh (z = 0 for a 2D mesh)
  std::vector<char> supported;             // per node: 1 = held fixed (the far side, tissue.geometry.support_depth)
  double entry_depth = 0.0;                // m, tip depth along the needle axis where it meets the tissue
  double entry_point[3] = {0, 0, 0};       // m, that point in the tissue frame
};

struct TissueSpec {
  // An imported geometry sets the block to the smallest one of the tissue frame (x from the entry
  // plane 0, y and z centred) that holds it.
  double length = 0.0;  // m, block extent along the insertion axis (entry face to exit face)
  double width = 0.0;   // m
  double height = 0.0;  // m
  std::shared_ptr<const ImportedGeometry> geometry;  // tissue.geometry; null = the block itself is the tissue
  std::vector<LayerSpec> layers;  // stacked from the entry face, thicknesses sum to length (imported geometry: its groups by name)
  std::vector<InclusionSpec> inclusions;
  // Index of the layer at depth x from the entry face (the last one beyond the block).
  std::size_t layerAt(double x) const;
};

enum class TipType { Bevel, Conical, Blunt };

struct NeedleSpec {
  double outer_diameter = 0.0;  // m
  double inner_diameter = 0.0;  // m (0 = solid)
  double length = 0.0;          // m
  double bevel_angle = 0.0;     // rad (tip angle alpha)
  TipType tip = TipType::Bevel;
  double youngs_modulus = 0.0;  // Pa
  double poisson = 0.3;
  double density = 0.0;  // kg/m^3
};

struct MotionSegment {
  enum class Kind { Insert, Pause, Retract, Rotate };
  Kind kind = Kind::Insert;
  double speed = 0.0;       // m/s, > 0 (Insert, Retract)
  double to_depth = 0.0;    // m, needle tip depth along its axis at the end (Insert, Retract)
  double duration = 0.0;    // s (Pause; Rotate derived from angle/rate)
  double angle = 0.0;       // rad (Rotate)
  double rate = 0.0;        // rad/s (Rotate; spin rate while inserting)
  bool axial = true;        // Rotate: about the needle axis (bevel) or in the insertion plane (base)
  double duty_cycle = 0.0;  // Insert: fraction of time spinning (0 = no spinning)
};

struct InsertionSpec {
  double entry_angle = 1.5707963267948966;  // rad, between needle and surface (90 deg = normal)
  double entry_offset = 0.0;                // m, entry point from the centre of the entry face
  double start_depth = 0.0;                 // m, tip position at t = 0 (negative = outside)
  double bevel_orientation = 0.0;           // rad, initial axial orientation of the bevel
  std::vector<MotionSegment> segments;
};

struct LumpedModelSpec {
  double relaxation_time = 0.0;  // s, decay of the held friction during pauses (0 = none)
};

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

// Real-time 3D FE engine (tetrahedral block, docs/models/realtime3d.md).
struct Realtime3dModelSpec {
  int nodes_depth = 41;          // nodes along the insertion axis (block.length)
  int nodes_lateral = 16;        // nodes across the width (block.width)
  int nodes_height = 16;         // nodes across the height (block.height)
  double refinement = 8.0;       // coarsest / finest lateral element size (finest on the path)
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
  std::vector<MarkerSpec> markers;
};

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
  bool cfemp = false;                // needle contact: CFEMP particle-to-surface (eqs 22-24); false: grid (eqs 14-21)
  double cfemp_element_size = 0.0;   // m, d_e of the eq 22 gap rule (0: the exact surface, gap d_p/2)
  double flip = 1.0;                 // FLIP fraction (1 = eq 4)
  double time_step_factor = 0.4;     // k_t, eq 26
  double mass_scaling = 1.0;         // factor on the particle masses (eq 28 discussion)
  int margin = 3;                    // grid cells beyond the block
  int threads = 0;                   // 0 = all cores
  // Face conditions: entry (depth 0), exit, y_min, y_max, z_min, z_max; each
  // "free", "fixed", "roller" or "non-reflecting".
  std::vector<std::string> faces{"free", "fixed", "free", "free", "free", "free"};
  double field_interval = 0.5;       // s, particle fields for ParaView (0 = none)
  double marker_depth_step = 0.0;    // m, marker rows each time the tip advances this far (0 = output interval)
  std::vector<MpmMarkerSpec> markers;
  MeasuredCurve measured_force;      // CSV: depth and force
  MeasuredMarkers measured_markers;  // CSV: depth and <name>_ux, <name>_uy per marker (eq 37)
};

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
};

struct ModelSpec {
  std::string engine = "lumped";  // lumped (others are listed in docs/scenario-format.md)
  double time_step = 1e-3;        // s, output and integration step
  LumpedModelSpec lumped;
  SteeringModelSpec steering;
  Realtime2dModelSpec realtime2d;
  Realtime3dModelSpec realtime3d;
  MpmModelSpec mpm;
  ExplicitModelSpec explicit_fe;  // `model.explicit` in a scenario
};

struct OutputSpec {
  std::string directory;    // empty = results/<scenario name>
  double interval = 0.0;    // s, sampling interval of the time series (0 = every step)
  double checkpoint_interval = 600.0;  // s of wall-clock time between checkpoints (0 = none; io/checkpoint.hpp)
  double max_steps = 1e6;   // run budget: the most steps an engine's estimate may reach (engines/step_guard.hpp)
  bool html = true;
  bool csv = true;
  // The units the terminal and the report show results in (output.units, else the unit
  // written most often per dimension in the file, else SI); files keep SI.
  units::DisplayUnits units;
};

struct Scenario {
  std::string name = "scenario";
  std::string description;
  std::string source;  // file it came from, or "<built-in default>"
  // Every field as the reader understood it (given or default), as JSON in the
  // scenario file's own schema with SI quantities: summary.json's "scenario",
  // readable again as a scenario. Empty for a Scenario built in code.
  std::string understood;
  // Where the file gives each field (path as in docs/scenario-format.md, e.g.
  // insertion.profile[0].insert.speed); see where().
  std::map<std::string, SourceLocation> given_at;
  TissueSpec tissue;
  NeedleSpec needle;
  InsertionSpec insertion;
  ModelSpec model;
  OutputSpec output;

  // The tip depth at the end of the motion profile and the largest reached.
  double maxDepth() const;
  double totalDuration() const;
  // The file, line and column that give `field`; for a section or list, its first
  // given field; the file alone when the field is not given (a default).
  SourceLocation where(const std::string& field) const;
};

}  // namespace needlesim
