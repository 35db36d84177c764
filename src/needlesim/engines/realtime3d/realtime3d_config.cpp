// Scenario -> realtime3d Session configuration: per layer the element material, friction,
// cutting and puncture at the path points; bonded inclusions as material spheres, or an
// imported tet mesh (tissue.geometry) with its groups; refusals of what the engine does not model.
#include <fmt/format.h>

#include <cmath>
#include <numbers>

#include "needlesim/core/error.hpp"
#include "needlesim/engines/realtime/scenario_config.hpp"
#include "needlesim/engines/realtime3d/realtime3d_engine.hpp"
#include "needlesim/engines/steering/steering_engines.hpp"
#include "needlesim/materials/material_spec.hpp"

namespace needlesim::engines {

using namespace realtime3d;

namespace {

ElasticMaterial elasticOf(const materials::MaterialSpec& m) {
  const auto mod = materials::smallStrainModuli(m);  // small-strain limit of any law
  return {mod.youngs(), mod.poisson(), m.density};
}

// Bonded inclusions in mesh coordinates: spheres, or cylinders along z as a stack of the
// elements within the radius of their axis (a sphere of the block's height would not do).
void addInclusions(const Scenario& sc, TissueConfig& t) {
  const Eigen::Vector3d shift = needle::cornerShift(sc.tissue);
  for (std::size_t i = 0; i < sc.tissue.inclusions.size(); ++i) {
    const auto& I = sc.tissue.inclusions[i];
    if (I.shape == InclusionSpec::Shape::Mesh) {  // its elements carry it (ImportedGeometry::region)
      t.regions.push_back({Eigen::Vector3d(I.x, I.y, I.z) + shift, I.radius, elasticOf(I.material)});
      continue;
    }
    if (I.shape != InclusionSpec::Shape::Sphere)
      refuseRealtime(sc, "realtime3d", fmt::format("tissue.inclusions[{}].shape", i),
                     "only spherical inclusions are modelled (material spheres of the tetrahedral block)", "sphere");
    t.regions.push_back({Eigen::Vector3d(I.x, I.y, I.z) + shift, I.radius, elasticOf(I.material)});
  }
}

// An imported geometry: tetrahedra, one layer (friction, cutting and puncture along the path
// follow depth bands, not the mesh's groups), held where the geometry is supported, no markers.
void checkGeometry(const Scenario& sc) {
  const auto& g = sc.tissue.geometry;
  if (!g) return;
  if (g->mesh->dim != 3 || g->mesh->element != "tet4")
    throw InputError(sc.where("tissue.geometry.file"), "tissue.geometry.file", g->file,
                     fmt::format("realtime3d: the mesh is {}D of {} elements; realtime3d takes linear tetrahedra",
                                 g->mesh->dim, g->mesh->element),
                     "a 3D mesh of tet4 elements (a Gmsh .msh or .geo meshed with tetrahedra, or closed surfaces)");
  if (sc.tissue.layers.size() > 1)
    refuseRealtime(sc, "realtime3d", "tissue.layers",
                   fmt::format("an imported mesh takes one layer (with inclusions); {} has {} layers, whose friction, "
                               "cutting and puncture the engine would place by depth bands, not by the mesh's groups",
                               g->file, sc.tissue.layers.size()),
                   "one layer, or engine explicit (which follows the groups)");
  if (!sc.model.realtime3d.markers.empty())
    refuseRealtime(sc, "realtime3d", "model.realtime3d.markers",
                   "markers are placed in the generated block, not in an imported mesh", "no markers with tissue.geometry");
}

// The channel's curvature of path follow_tip: given, else engine kinematic's (model.steering.curvature,
// else the beam-on-foundation steady curvature of the tip loads, seed 002 section 4); 0 for a symmetric tip.
double channelCurvature(const Scenario& sc) {
  const auto& r = sc.model.realtime3d;
  if (!r.follow_tip || sc.needle.tip != TipType::Bevel) return 0.0;  // a symmetric tip cuts straight on
  if (r.curvature >= 0.0) return r.curvature;
  if (sc.model.steering.curvature >= 0.0) return sc.model.steering.curvature;
  return std::abs(steeringInputs(sc).kappa_bof);
}

TissueConfig tissueConfig(const Scenario& sc) {
  const auto& r = sc.model.realtime3d;
  TissueConfig t;
  t.material = elasticOf(sc.tissue.layers.front().material);
  if (sc.tissue.layers.size() > 1) {
    double x = 0.0;
    for (const auto& L : sc.tissue.layers) t.layers.emplace_back(x += L.thickness, elasticOf(L.material));
  }
  addInclusions(sc, t);
  t.block = {sc.tissue.length, sc.tissue.width, sc.tissue.height, r.nodes_depth, r.nodes_lateral, r.nodes_height,
             0.0, 0.0, r.refinement};
  t.lumped_mass = r.lumped_mass;
  t.rayleigh_alpha = r.rayleigh_alpha;  // eq 3.8
  t.rayleigh_beta = r.rayleigh_beta;
  t.newmark.gamma = r.newmark_gamma;    // eqs 3.2-3.3
  t.newmark.beta = r.newmark_beta;
  t.hold_sides = r.hold_sides;
  t.geometry = sc.tissue.geometry;
  t.coupling_spacing = r.coupling_spacing;
  t.coupling_radius = 0.5 * sc.needle.outer_diameter;
  if (r.relaxation) t.prony = sc.tissue.layers.front().material.prony;  // QLV, one series for the block
  t.backend = realtimeBackend(r.solver);
  t.reduced_max_modes = r.modes;
  t.follow_tip = r.follow_tip;
  t.channel_curvature = channelCurvature(sc);
  return t;
}

}  // namespace

SessionConfig realtime3dConfig(const Scenario& sc) {
  checkGeometry(sc);
  checkRealtimeLayers(sc, "realtime3d", sc.model.realtime3d.relaxation);
  checkRealtimeInclusions(sc, "realtime3d");
  SessionConfig c;
  c.tissue = tissueConfig(sc);
  c.needle = realtimeNeedle(sc, sc.model.realtime3d.tip_load_ratio);
  setRealtimeForces(sc, "realtime3d", c);
  return c;
}

}  // namespace needlesim::engines
