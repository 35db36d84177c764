// Scenario -> realtime3d Session configuration: per layer the element material, friction,
// cutting and puncture at the path nodes; bonded inclusions as material spheres (or
// cylinders across the height); refusals of what the engine does not model.
#include <fmt/format.h>

#include <cmath>
#include <numbers>

#include "needlesim/core/error.hpp"
#include "needlesim/engines/realtime/scenario_config.hpp"
#include "needlesim/engines/realtime3d/realtime3d_engine.hpp"
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
    if (I.shape != InclusionSpec::Shape::Sphere)
      refuseRealtime(sc, "realtime3d", fmt::format("tissue.inclusions[{}].shape", i),
                     "only spherical inclusions are modelled (material spheres of the tetrahedral block)", "sphere");
    t.regions.push_back({Eigen::Vector3d(I.x, I.y, I.z) + shift, I.radius, elasticOf(I.material)});
  }
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
  if (r.relaxation) t.prony = sc.tissue.layers.front().material.prony;  // QLV, one series for the block
  t.backend = realtimeBackend(r.solver);
  t.reduced_max_modes = r.modes;
  return t;
}

}  // namespace

SessionConfig realtime3dConfig(const Scenario& sc) {
  if (sc.tissue.geometry)
    refuseRealtime(sc, "realtime3d", "tissue.geometry", "an imported geometry is not meshed by realtime3d (it "
                   "generates a graded tetrahedral block)", "tissue.block, or engine explicit or mpm");
  checkRealtimeLayers(sc, "realtime3d", sc.model.realtime3d.relaxation);
  checkRealtimeInclusions(sc, "realtime3d");
  SessionConfig c;
  c.tissue = tissueConfig(sc);
  c.needle = realtimeNeedle(sc, sc.model.realtime3d.tip_load_ratio);
  setRealtimeForces(sc, "realtime3d", c);
  return c;
}

}  // namespace needlesim::engines
