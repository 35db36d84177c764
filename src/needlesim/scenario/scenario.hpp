#pragma once
// The typed scenario every engine receives: plain structs in SI units.
// Engines never parse YAML; scenario/reader.cpp builds this from a file.
#include <any>
#include <map>
#include <memory>
#include <string>
#include <typeindex>
#include <vector>

#include "needlesim/core/error.hpp"
#include "needlesim/core/units.hpp"
#include "needlesim/contact/friction_spec.hpp"
#include "needlesim/insertion/insertion_spec.hpp"
#include "needlesim/materials/material_spec.hpp"
#include "needlesim/needle/needle_spec.hpp"
#include "needlesim/scenario/plan_section.hpp"
// The engines' model.<engine> settings that are members of ModelSpec, declared beside each engine
// (engines/<engine>/<engine>_section.hpp); an engine may instead keep them in ModelSpec::spec<>().
#include "needlesim/engines/explicit/explicit_section.hpp"
#include "needlesim/engines/lumped/lumped_section.hpp"
#include "needlesim/engines/mpm/mpm_section.hpp"
#include "needlesim/engines/realtime2d/realtime2d_section.hpp"
#include "needlesim/engines/realtime3d/realtime3d_section.hpp"
#include "needlesim/engines/steering/steering_section.hpp"

namespace needlesim {

namespace mesh {
struct VolumeMesh;  // mesh/volume_mesh.hpp
}

struct LayerSpec {
  std::string name;
  double thickness = 0.0;            // m, along the surface normal
  materials::MaterialSpec material;  // constitutive law
  double puncture_force = 0.0;       // N, threshold of the pre-puncture stiffness force (0 = punctures on contact)
  double puncture_depth = 0.0;       // m, given instead of the force: the indentation at puncture (0 = not given)
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

struct ModelSpec {
  std::string engine = "lumped";  // lumped (others are listed in docs/scenario-format.md)
  double time_step = 1e-3;        // s, output and integration step
  LumpedModelSpec lumped;
  SteeringModelSpec steering;
  Realtime2dModelSpec realtime2d;
  Realtime3dModelSpec realtime3d;
  MpmModelSpec mpm;
  ExplicitModelSpec explicit_fe;  // `model.explicit` in a scenario

  // The settings of an engine that is no member above, one per spec type: the engine's section
  // (engines/<engine>/<engine>_section.cpp, registered in engines/registry.cpp) reads model.<engine>
  // into spec<Spec>() and the engine reads them there; a scenario built in code without them
  // reads the spec's defaults. A new engine thus needs no line here.
  template <class Spec>
  Spec& spec() {
    std::any& held = engine_specs[std::type_index(typeid(Spec))];
    if (!held.has_value()) held = Spec{};
    return std::any_cast<Spec&>(held);
  }
  template <class Spec>
  const Spec& spec() const {
    static const Spec defaults{};
    const auto it = engine_specs.find(std::type_index(typeid(Spec)));
    return it == engine_specs.end() ? defaults : std::any_cast<const Spec&>(it->second);
  }
  std::map<std::type_index, std::any> engine_specs;  // spec<>()'s store
};

struct OutputSpec {
  std::string directory;    // empty = results/<scenario name>
  double interval = 0.0;    // s, sampling interval of the time series (0 = every step)
  double checkpoint_interval = 600.0;  // s of wall-clock time between checkpoints (0 = none; results/checkpoint.hpp)
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
  // Read from a results folder's summary.json, which writes every field, given or default.
  bool from_record = false;
  TissueSpec tissue;
  NeedleSpec needle;
  InsertionSpec insertion;
  ModelSpec model;
  OutputSpec output;
  PlanSpec plan;  // `needlesim plan` (scenario/plan_section.hpp)

  // The tip depth at the end of the motion profile and the largest reached.
  double maxDepth() const;
  double totalDuration() const;
  // The file, line and column that give `field`; for a section or list, its first
  // given field; the file alone when the field is not given (a default).
  SourceLocation where(const std::string& field) const;
};

}  // namespace needlesim
