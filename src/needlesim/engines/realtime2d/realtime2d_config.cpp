// Scenario -> realtime2d Session configuration: per layer what the 2D FE honours
// (element material, friction, cutting and puncture at the path nodes), bonded
// inclusions as material discs, and clear refusals of what it cannot model.
#include <fmt/format.h>

#include <cmath>
#include <numbers>

#include "needlesim/core/error.hpp"
#include "needlesim/engines/realtime/scenario_config.hpp"
#include "needlesim/engines/realtime2d/realtime2d_engine.hpp"
#include "needlesim/materials/material_spec.hpp"

namespace needlesim::engines {

using namespace realtime2d;

namespace {

ElasticMaterial elasticOf(const materials::MaterialSpec& m, const Realtime2dModelSpec& r) {
  const auto mod = materials::smallStrainModuli(m);  // small-strain limit of any law
  ElasticMaterial e;
  e.E = mod.youngs();
  e.nu = mod.poisson();
  e.density = m.density;
  e.thickness = r.thickness;
  e.plane_strain = r.plane_strain;
  return e;
}

[[noreturn]] void refuse(const Scenario& sc, const std::string& field, const std::string& problem,
                         const std::string& allowed) {
  refuseRealtime(sc, "realtime2d", field, problem, allowed);
}

// The 2D slab models the insertion plane z = 0: a sphere must cut it.
void checkInclusions(const Scenario& sc) {
  checkRealtimeInclusions(sc, "realtime2d");
  for (std::size_t i = 0; i < sc.tissue.inclusions.size(); ++i) {
    const auto& I = sc.tissue.inclusions[i];
    if (I.shape == InclusionSpec::Shape::Sphere && std::abs(I.z) >= I.radius)
      refuse(sc, fmt::format("tissue.inclusions[{}].elevation", i),
             fmt::format("the sphere (elevation {:g} mm, radius {:g} mm) does not cut the insertion plane z = 0 "
                         "that the 2D slab models",
                         I.z * 1e3, I.radius * 1e3),
             "|elevation| < radius");
  }
}

// Each bonded inclusion's section in the insertion plane (z = 0), in mesh coordinates.
std::vector<MaterialRegion> inclusionRegions(const Scenario& sc) {
  const Eigen::Vector2d shift = needle::cornerShift(sc.tissue).head<2>();
  std::vector<MaterialRegion> regions;
  for (const auto& I : sc.tissue.inclusions) {
    MaterialRegion g;
    g.centre = Eigen::Vector2d(I.x, I.y) + shift;
    g.radius = I.shape == InclusionSpec::Shape::Cylinder ? I.radius : std::sqrt(I.radius * I.radius - I.z * I.z);
    g.material = elasticOf(I.material, sc.model.realtime2d);
    regions.push_back(g);
  }
  return regions;
}

// An imported mesh (tissue.geometry) carries one layer's friction, cutting and puncture along
// the path (the depth bands of several layers do not follow its groups), held sides only, and
// no markers (they are placed in the generated grid's cells).
void checkGeometry(const Scenario& sc) {
  const auto& g = sc.tissue.geometry;
  if (!g) return;
  if (sc.tissue.layers.size() > 1)
    refuse(sc, "tissue.layers",
           fmt::format("an imported mesh takes one layer (with inclusions); {} has {} layers, whose friction, cutting "
                       "and puncture the engine would place by depth bands, not by the mesh's groups",
                       g->file, sc.tissue.layers.size()),
           "one layer, or engine explicit (which follows the groups)");
  const auto& r = sc.model.realtime2d;
  if (r.spring_boundary)
    refuse(sc, "model.realtime2d.boundary", "an imported mesh is held at its supported far side and its sides "
                                            "(tissue.geometry.support_depth); spring supports need the generated block",
           "boundary: held");
  if (!r.markers.empty())
    refuse(sc, "model.realtime2d.markers", "markers are placed in the generated block's grid, not in an imported mesh",
           "no markers with tissue.geometry");
}

TissueConfig tissueConfig(const Scenario& sc) {
  const auto& r = sc.model.realtime2d;
  TissueConfig t;
  t.material = elasticOf(sc.tissue.layers.front().material, r);
  if (sc.tissue.layers.size() > 1) {
    double x = 0.0;
    for (const auto& L : sc.tissue.layers) t.layers.emplace_back(x += L.thickness, elasticOf(L.material, r));
  }
  t.regions = inclusionRegions(sc);
  t.geometry = sc.tissue.geometry;
  t.mesh.length = sc.tissue.length;
  t.mesh.width = sc.tissue.width;
  t.mesh.nodes_depth = r.nodes_depth;
  t.mesh.nodes_lateral = r.nodes_lateral;
  t.mesh.grading = r.refinement;
  t.lumped_mass = r.lumped_mass;
  t.rayleigh_alpha = r.rayleigh_alpha;  // eq 3.8
  t.rayleigh_beta = r.rayleigh_beta;
  t.newmark.gamma = r.newmark_gamma;    // eqs 3.2-3.3
  t.newmark.beta = r.newmark_beta;
  t.support_stiffness = r.spring_boundary ? r.spring_stiffness : 0.0;
  if (r.relaxation) t.prony = sc.tissue.layers.front().material.prony;  // QLV relaxation (one set for the block)
  t.stiffening_factor = r.stiffening_factor;
  t.stiffening_radius = r.stiffening_radius;
  t.backend = realtimeBackend(r.solver);
  return t;
}

}  // namespace

SessionConfig realtime2dConfig(const Scenario& sc) {
  checkRealtimeLayers(sc, "realtime2d", sc.model.realtime2d.relaxation);
  checkInclusions(sc);
  checkGeometry(sc);
  SessionConfig c;
  c.tissue = tissueConfig(sc);
  c.needle = realtimeNeedle(sc, sc.model.realtime2d.tip_load_ratio);
  setRealtimeForces(sc, "realtime2d", c);
  return c;
}

}  // namespace needlesim::engines
