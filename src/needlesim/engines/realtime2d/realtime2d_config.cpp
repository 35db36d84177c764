// Scenario -> realtime2d Session configuration: per layer what the 2D FE honours
// (element material, friction, cutting and puncture at the path nodes), bonded
// inclusions as material discs, and clear refusals of what it cannot model.
#include <fmt/format.h>

#include <cmath>
#include <numbers>

#include "needlesim/core/error.hpp"
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
  throw InputError(sc.where(field), field, "", "realtime2d: " + problem, allowed);
}

bool sameProny(const std::vector<materials::PronyTerm>& a, const std::vector<materials::PronyTerm>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (a[i].g != b[i].g || a[i].tau != b[i].tau) return false;
  return true;
}

// One relaxation function for the whole block: every back-end relaxes K as a whole
// (K G(t), the modal and reduced ones with one history per mode of K), so Prony terms
// that differ between materials would couple the modes.
void checkOneRelaxation(const Scenario& sc) {
  if (!sc.model.realtime2d.relaxation) return;
  const auto& p0 = sc.tissue.layers.front().material.prony;
  const std::string why =
      "differs from layer 0's; the realtime2d back-ends relax the whole stiffness K with one Prony series "
      "(the modal and reduced ones keep one relaxation history per mode of K)";
  const std::string allowed = "the Prony terms of layer 0 in every material, or model.realtime2d.relaxation: off";
  for (std::size_t i = 1; i < sc.tissue.layers.size(); ++i)
    if (!sameProny(sc.tissue.layers[i].material.prony, p0))
      refuse(sc, fmt::format("tissue.layers[{}].material.prony", i), why, allowed);
  for (std::size_t i = 0; i < sc.tissue.inclusions.size(); ++i)
    if (!sameProny(sc.tissue.inclusions[i].material.prony, p0))
      refuse(sc, fmt::format("tissue.inclusions[{}].material.prony", i), why, allowed);
}

void checkLayers(const Scenario& sc) {
  for (std::size_t i = 0; i < sc.tissue.layers.size(); ++i) {
    const auto& L = sc.tissue.layers[i];
    if (L.toughness != 0.0)
      refuse(sc, fmt::format("tissue.layers[{}].interaction.toughness", i),
             "the tissue is cut by the constant force of eq 3.24 (cutting.force); a rupture toughness is not modelled",
             "no toughness (an engine with a cohesive model uses it)");
    if (L.interaction_stiffness != 0.0)
      refuse(sc, fmt::format("tissue.layers[{}].interaction.K_T", i),
             "the needle-tissue interaction is the FE coupling on the path nodes; K_T is not used",
             "no K_T (the steering engines use it)");
  }
  checkOneRelaxation(sc);
}

// Bonded inclusions only; inside one the shaft meets the layer's Karnopp friction and cutting.
void checkInclusions(const Scenario& sc) {
  for (std::size_t i = 0; i < sc.tissue.inclusions.size(); ++i) {
    const auto& I = sc.tissue.inclusions[i];
    const auto& around = sc.tissue.layers[sc.tissue.layerAt(I.x)];
    if (I.sliding)
      refuse(sc, fmt::format("tissue.inclusions[{}].interface", i),
             "a sliding inclusion (a separate body in contact) is not modelled: the 2D mesh is one body",
             "interface: bonded");
    if (I.friction_coefficient != around.friction.coefficient)
      refuse(sc, fmt::format("tissue.inclusions[{}].friction", i),
             "the shaft friction is the Karnopp law of the layer around it (eq 3.23); a Coulomb coefficient of "
             "the inclusion's own is not modelled",
             "the layer's friction (leave it out)");
    if (I.toughness != 0.0)
      refuse(sc, fmt::format("tissue.inclusions[{}].toughness", i),
             "the tissue is cut by the constant force of eq 3.24; a rupture toughness is not modelled",
             "no toughness");
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

// The reader marks a puncture depth with a negative value: convert it by eq 3.16 with
// the layer's material.
double punctureForce(const LayerSpec& L, const ElasticMaterial& m, const Scenario& sc) {
  if (L.puncture_force >= 0.0) return L.puncture_force;
  const forces::StiffnessLaw law{m.E, m.nu, sc.needle.bevel_angle, sc.insertion.entry_angle};
  return law.force(-L.puncture_force);
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
  t.backend = r.solver == "direct"    ? Backend::Direct
              : r.solver == "modal"   ? Backend::Modal
              : r.solver == "reduced" ? Backend::Reduced
                                      : Backend::Auto;
  return t;
}

NeedleConfig needleConfig(const Scenario& sc) {
  const auto& nd = sc.needle;
  NeedleConfig n;
  n.length = nd.length;
  n.EI = nd.youngs_modulus * std::numbers::pi / 64.0 * (std::pow(nd.outer_diameter, 4) - std::pow(nd.inner_diameter, 4));
  n.bevel_angle = nd.bevel_angle;
  // A symmetric (conical, blunt) tip carries no transverse load.
  n.tip_load_ratio = nd.tip == TipType::Bevel ? sc.model.realtime2d.tip_load_ratio : 0.0;
  return n;
}

}  // namespace

SessionConfig realtime2dConfig(const Scenario& sc) {
  checkLayers(sc);
  checkInclusions(sc);
  SessionConfig c;
  c.tissue = tissueConfig(sc);
  c.needle = needleConfig(sc);
  const auto& L0 = sc.tissue.layers.front();
  c.friction = L0.friction;
  c.cutting_force = L0.cutting_force;
  c.puncture_force = punctureForce(L0, c.tissue.material, sc);
  for (std::size_t i = 0; i < c.tissue.layers.size(); ++i) {
    const auto& L = sc.tissue.layers[i];
    c.layers.push_back({c.tissue.layers[i].first, L.friction, L.cutting_force,
                        punctureForce(L, c.tissue.layers[i].second, sc)});
  }
  c.frame = needle::InsertionFrame::fromInsertion(sc.insertion);
  c.dt = sc.model.time_step;
  if (sc.insertion.entry_angle < 0.25 * std::numbers::pi - 1e-12)
    throw SolverError(fmt::format("realtime2d: entry angle {:g} deg is below the 45 deg the path-node coupling "
                                  "supports (the needle axis must be within 45 deg of the entry-face normal)",
                                  sc.insertion.entry_angle * 180.0 / std::numbers::pi));
  return c;
}

}  // namespace needlesim::engines
