// MPM engine set-up: scenario -> MpmSolver (seed 000 sections 3-4). The
// solver works in the tissue frame of needle/insertion_frame.hpp moved to the
// block's corner. docs/models/mpm.md.
#include "needlesim/engines/mpm/mpm_engine.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <tuple>
#include <utility>

#ifdef _OPENMP
#include <omp.h>
#endif

#include "needlesim/core/error.hpp"
#include "needlesim/engines/mpm/cfemp_contact.hpp"
#include "needlesim/engines/mpm/geometry_fill.hpp"
#include "needlesim/engines/run_cost.hpp"
#include "needlesim/insertion/motion_profile.hpp"
#include "needlesim/mesh/volume_mesh.hpp"
#include "needlesim/tissue/regions.hpp"

namespace needlesim::engines {

using namespace mpm;

namespace {

FaceBC faceOf(const std::string& s) {
  if (s == "fixed") return FaceBC::Fixed;
  if (s == "roller") return FaceBC::Roller;
  if (s == "non-reflecting") return FaceBC::NonReflecting;
  return FaceBC::Free;
}

InputError refusal(const Scenario& sc, const std::string& field, const std::string& value, const std::string& problem,
                   const std::string& allowed) {
  return InputError(sc.where(field), field, value, "mpm: " + problem, allowed);
}

// One solver material per region (tissue/regions.hpp: layers, then inclusions). Where the Coulomb
// coefficients differ, each material takes its own to the needle contact (eq 20 where its point is
// nearest to the needle); else the needle's one coefficient applies.
std::vector<MpmMaterial> tissueMaterials(const TissueSpec& t) {
  std::vector<MpmMaterial> out;
  const auto regions = tissue::regions(t);
  for (const auto& r : regions) out.push_back(MpmMaterial::fromSpec(r.material));
  if (!tissue::uniformFriction(regions))
    for (std::size_t i = 0; i < out.size(); ++i) out[i].rigidFriction = regions[i].friction;
  return out;
}

// Sliding inclusions form body 1, in contact with the tissue (body 0) through
// the pair penalty with the inclusions' interface friction.
void configureBodies(const Scenario& sc, MpmConfig& c) {
  const auto& inc = sc.tissue.inclusions;
  for (std::size_t i = 0; i < inc.size(); ++i) {
    if (!inc[i].sliding) continue;
    const std::string field = fmt::format("tissue.inclusions[{}]", i);
    if (sc.model.mpm.cfemp)
      throw refusal(sc, field + ".interface", "sliding",
                    "the CFEMP needle contact (model.mpm.contact: cfemp) is not verified with a second body",
                    "interface: bonded, or model.mpm.contact: grid");
    if (c.bodies == 2 && inc[i].interface_friction != c.friction)
      throw refusal(sc, field + ".interface_friction", fmt::format("{:g}", inc[i].interface_friction),
                    "all sliding inclusions form one body with one Coulomb coefficient against the tissue",
                    fmt::format("{:g} (as the first sliding inclusion)", c.friction));
    c.bodies = 2;
    c.friction = inc[i].interface_friction;  // the pair's Coulomb coefficient (eqs 19-21)
  }
}

// CFEMP applies the needle's one Coulomb coefficient to every point.
void checkCfempFriction(const Scenario& sc, double mu) {
  if (!sc.model.mpm.cfemp) return;
  const auto& t = sc.tissue;
  for (std::size_t i = 0; i < t.layers.size(); ++i)
    if (t.layers[i].friction.coefficient != mu)
      throw refusal(sc, fmt::format("tissue.layers[{}].friction.coefficient", i),
                    fmt::format("{:g}", t.layers[i].friction.coefficient),
                    "differs from layer 0; the CFEMP contact (model.mpm.contact: cfemp) has one coefficient",
                    fmt::format("{:g}, or model.mpm.contact: grid", mu));
  for (std::size_t i = 0; i < t.inclusions.size(); ++i)
    if (t.inclusions[i].friction_coefficient != mu)
      throw refusal(sc, fmt::format("tissue.inclusions[{}].friction", i),
                    fmt::format("{:g}", t.inclusions[i].friction_coefficient),
                    "differs from layer 0's friction.coefficient; the CFEMP contact has one coefficient",
                    fmt::format("{:g}, or model.mpm.contact: grid", mu));
}

// The cut along the bevel's edges lifts what lies inside the needle's outline onto its face: a
// rule of the CFEMP contact, which resolves the needle's surface at the points.
void checkCut(const Scenario& sc) {
  if (sc.model.mpm.cut != "edges" || sc.model.mpm.cfemp) return;
  throw refusal(sc, "model.mpm.cut", "edges", "the cut along the bevel's edges needs the CFEMP contact",
                "cut: axis, or model.mpm.contact: cfemp");
}

MpmConfig solverConfig(const Scenario& sc) {
  const MpmModelSpec& m = sc.model.mpm;
  MpmConfig c;
  const double h = m.grid_spacing;
  const Vec3 ext(sc.tissue.length, sc.tissue.width, sc.tissue.height);
  c.h = h;
  c.origin = Vec3::Constant(-m.margin * h);
  for (int d = 0; d < 3; ++d)
    c.cells[static_cast<std::size_t>(d)] = static_cast<int>(std::ceil(ext[d] / h - 1e-9)) + 2 * m.margin;
  c.shape = m.bspline ? Shape::BSpline2 : Shape::Linear;
  c.update = m.musl ? Update::MUSL : Update::USL;
  c.fbar = m.fbar;
  c.flip = m.flip;
  c.timeStepFactor = m.time_step_factor;  // eq 26
  c.massScaling = m.mass_scaling;         // eq 28 discussion
  c.threads = m.threads;
  // Below ~20k points the per-step barriers of a second thread cost more than it gains.
  const double points = ext.prod() / std::pow(m.particle_spacing, 3);
  if (c.threads == 0 && points < 2e4) c.threads = 1;
  c.boxLo = Vec3::Zero();
  c.boxHi = ext;
  for (std::size_t f = 0; f < 6; ++f) c.faces[f] = faceOf(m.faces[f]);
  configureBodies(sc, c);
  return c;
}

// An imported geometry (tissue.geometry) replaces the block's faces by its supported side
// (geometry_fill.hpp); tetrahedra only.
void configureGeometry(const Scenario& sc, MpmSetup& s) {
  const auto& g = sc.tissue.geometry;
  if (!g) return;
  if (g->mesh->element != "tet4")
    throw refusal(sc, "tissue.geometry", g->file,
                  fmt::format("fills tetrahedral meshes with material points, not {} elements", g->mesh->element),
                  "a tetrahedral mesh (Gmsh: Mesh 3 of a script, or surfaces, which are meshed into tetrahedra)");
  if (sc.model.mpm.faces != MpmModelSpec{}.faces)  // the defaults (mpm_section.cpp) are the only ones
    throw refusal(sc, "model.mpm.faces", "given",
                  "with tissue.geometry the geometry's supported side (tissue.geometry.support_depth) is held, "
                  "not the faces of its bounding box",
                  "no model.mpm.faces with tissue.geometry");
  for (auto& f : s.config.faces) f = FaceBC::Free;
  s.config.heldNodes = heldGridNodes(*g, s.config, s.shift);
}

RigidBody rigidNeedle(const Scenario& sc, const Vec3& axis) {
  RigidBody n;
  n.kind = RigidBody::Kind::Needle;
  n.tip = sc.needle.tip == TipType::Bevel     ? RigidBody::Tip::Bevel
          : sc.needle.tip == TipType::Conical ? RigidBody::Tip::Conical
                                              : RigidBody::Tip::Blunt;
  n.radius = 0.5 * sc.needle.outer_diameter;
  n.tipAngle = sc.needle.bevel_angle;  // bevel: face to the axis; cone: half-angle
  n.axis = axis;
  // Eq 20 where no material sets its own (every tissue material does: tissueMaterials).
  n.friction = sc.tissue.layers.front().friction.coefficient;
  n.length = sc.needle.length;
  n.surfaceContact = sc.model.mpm.cfemp;            // eqs 22-24
  n.tipFriction = sc.model.mpm.tip_friction;
  n.elementSize = sc.model.mpm.cfemp_element_size;  // d_e of eq 22
  n.parting = sc.model.mpm.parting != "none";      // needle_cut.cpp
  n.cutAlongEdges = sc.model.mpm.cut == "edges";
  return n;
}

}  // namespace

MpmSetup mpmSetup(const Scenario& sc) {
  MpmSetup s;
  s.config = solverConfig(sc);
  s.materials = tissueMaterials(sc.tissue);
  if (s.materials.size() > 255)
    throw refusal(sc, "tissue.inclusions", fmt::format("{}", sc.tissue.inclusions.size()),
                  "at most 255 layers and inclusions together", "fewer layers or inclusions");
  s.frame = needle::InsertionFrame::fromInsertion(sc.insertion);
  s.shift = needle::cornerShift(sc.tissue);
  s.entry = s.frame.entry + s.shift;
  configureGeometry(sc, s);
  s.needle = rigidNeedle(sc, s.frame.axial);
  checkCfempFriction(sc, s.needle.friction);
  checkCut(sc);
  if (sc.model.mpm.parting == "path") s.cutDepth = sc.maxDepth();
  placeNeedle(s.needle, s, 0.0, s.frame.bevelSide(), 0.0);
  return s;
}

namespace {
// The material points addTissue makes: each layer's block lattice, or the lattice of the
// block kept inside an imported geometry.
double materialPoints(const Scenario& sc, const MpmSetup& s) {
  const TissueSpec& t = sc.tissue;
  const double dp = sc.model.mpm.particle_spacing;
  if (t.geometry) {
    const std::vector<int> material =
        latticeRegions(*t.geometry, Lattice(Vec3::Zero(), Vec3(t.length, t.width, t.height), dp), s.shift);
    return static_cast<double>(std::count_if(material.begin(), material.end(), [](int m) { return m >= 0; }));
  }
  double n = 0.0, x = 0.0;
  for (const auto& layer : t.layers) {
    n += static_cast<double>(Lattice(Vec3(x, 0, 0), Vec3(x + layer.thickness, t.width, t.height), dp).size());
    x += layer.thickness;
  }
  return n;
}

// The drag strain of the block (run_cost.hpp): the shaft's friction over the block's cross-section,
// mu_f pi d_c travel / (width x height), d_c the needle's contact diameter.
double dragStrain(const Scenario& sc, double contactDiameter, double travel) {
  const TissueSpec& t = sc.tissue;
  const double mu = t.layers.front().friction.coefficient;
  return mu * std::numbers::pi * contactDiameter * travel / (t.width * t.height);
}

// The steps a run takes per step of the first step's count (run_cost.hpp): a strain-stiffening
// tissue the needle compresses shortens eq 26's step, by contact kind (grid contact ploughing or
// parting, CFEMP parting growing with the block's drag strain); a sliding inclusion's pair contact
// shortens it and adds its pair search.
double mpmStepGrowth(const Scenario& sc, const MpmSetup& s) {
  using namespace run_cost;
  double growth = kMpmGrowth;
  const bool stiffens = std::any_of(s.materials.begin(), s.materials.end(),
                                    [](const MpmMaterial& m) { return m.law.kind == materials::LawKind::Fung; });
  if (stiffens) {
    const MpmModelSpec& m = sc.model.mpm;
    const bool parts = sc.needle.tip == TipType::Bevel && m.parting != "none";
    const double h = s.config.h, travel = std::max(0.0, sc.maxDepth() - sc.insertion.start_depth);
    const double d = sc.needle.outer_diameter + (m.cfemp ? m.cfemp_element_size : 0.0);  // eq 22's contact reach
    const double cells = travel / h * d / h;
    const double k = !parts   ? kMpmGrowthPloughing
                     : m.cfemp ? kMpmGrowthCfempParting + kMpmGrowthCfempDrag * dragStrain(sc, d, travel)
                               : kMpmGrowthParting;
    growth += k * cells;
  }
  const auto& inc = sc.tissue.inclusions;
  if (std::any_of(inc.begin(), inc.end(), [](const InclusionSpec& i) { return i.sliding; })) growth *= kMpmSliding;
  return growth;
}

// The needle's length in the tissue averaged over the motion (the steps are about even in time).
double meanInsertedLength(const Scenario& sc) {
  const MotionProfile motion(sc.insertion);
  constexpr int kSamples = 256;
  double sum = 0.0;
  for (int i = 0; i < kSamples; ++i) sum += std::max(0.0, motion.at((i + 0.5) / kSamples * motion.duration()).depth);
  return sum / kSamples;
}

// The needle contact's CPU seconds per step on one thread, averaged over the run (run_cost.hpp), as
// {parallel, serial}: the cut's strip test of every point (planCut) and the crossing tests and
// renormalised supports of the points in reach of the strip; CFEMP's serial pair search, a bucket
// test of every point and the facet tests of the points in the needle surface's buckets
// (NeedleSurface::nearest) along the length in the tissue.
std::pair<double, double> mpmContactSeconds(const Scenario& sc, const MpmSetup& s, double points) {
  using namespace run_cost;
  const MpmModelSpec& m = sc.model.mpm;
  const RigidBody& n = s.needle;
  const double dp = m.particle_spacing, h = s.config.h, inserted = meanInsertedLength(sc);
  double parallel = 0.0, serial = 0.0;
  if (n.tip == RigidBody::Tip::Bevel && n.parting) {  // needle_cut.cpp
    const double reach = (s.config.shape == Shape::Linear ? 1.0 : 1.5) * std::sqrt(3.0) * h;
    const double strip = 2 * reach * 2 * (n.radius + reach) * (inserted + 2 * reach) / (dp * dp * dp);
    parallel += kMpmCutScan * points + kMpmCutStripPoint * std::min(points, strip);
  }
  if (n.surfaceContact) {  // cfemp_contact.cpp
    NeedleSurface surface;
    surface.build(n, dp, 0.5 * dp, h);
    const double perLength = static_cast<double>(surface.items.size()) / surface.dim[0] * surface.cell * surface.cell /
                             (dp * dp * dp);  // facet tests per metre of needle in the tissue
    serial += kMpmCfempScan * points + kMpmFacetTest * perLength * inserted;
  }
  return {parallel, serial};
}

// The threads of the point loops (mpm_solver.cpp): model.mpm.threads, else OpenMP's default.
int mpmThreads(const MpmSetup& s) {
#ifdef _OPENMP
  return s.config.threads > 0 ? s.config.threads : omp_get_max_threads();
#else
  return 1;
#endif
}
}  // namespace

// The needle is rigid and moves at the prescribed speed whatever the step: it
// meets the tissue at grid nodes, so a step must not carry it across a cell.
StepPlan mpmStepPlan(const Scenario& sc) {
  const MpmSetup s = mpmSetup(sc);
  double wave = 0.0;  // the fastest dilatational wave of the materials at rest (eq 27)
  for (const MpmMaterial& m : s.materials) {
    double W = 0.0, c = 0.0;
    evaluateStress(m, Mat3::Identity(), s.config.massScaling, W, c);
    wave = std::max(wave, c);
  }
  const MpmModelSpec& m = sc.model.mpm;
  StepPlan p;
  p.engine = "mpm";
  p.dt = s.config.timeStepFactor * s.config.h / wave;  // eqs 25-26
  p.dtSetBy = fmt::format("eqs 25-26: model.mpm.time_step_factor {:g} x grid_spacing {:g} mm / the wave speed "
                          "{:.3g} m/s of the tissue with mass_scaling {:g}",
                          m.time_step_factor, m.grid_spacing * 1e3, wave, m.mass_scaling);
  p.dtField = "model.mpm.mass_scaling";
  p.dtValue = fmt::format("{:g}", m.mass_scaling);
  p.stepAllowed = massScaledStep(p.dtField, m.mass_scaling, p.dt, "a lower model.mpm.time_step_factor");
  p.adaptive = true;  // eq 26 each step: the wave speed rises as the tissue stiffens and moves
  p.fewerSteps = "a larger model.mpm.mass_scaling or grid_spacing, or a tissue nu further from 0.5 (the wave "
                 "speed, and so the step count, grows as 1/sqrt(1 - 2 nu))";
  p.spacing = s.config.h;
  p.spacingName = "the grid spacing (model.mpm.grid_spacing)";
  p.updatesPerStep = materialPoints(sc, s);
  p.updates = "points";
  if (!m.cuda) {  // run_cost.hpp holds the CPU's costs; a GPU run gets the step count alone
    p.secondsPerUpdate = run_cost::kMpmPoint;
    std::tie(p.secondsPerStep, p.serialSecondsPerStep) = mpmContactSeconds(sc, s, p.updatesPerStep);
    p.setupSeconds = run_cost::kMpmSetupPerPoint * p.updatesPerStep;
    p.stepGrowth = mpmStepGrowth(sc, s);
    p.threads = mpmThreads(s);
  }
  return p;
}

Vec3 needleTip(const MpmSetup& s, double depth, const Vec3& bevelSide) {
  const Vec3 c = s.frame.onAxis(depth);  // axis point level with the tip
  return s.needle.tip == RigidBody::Tip::Bevel ? Vec3(c - s.needle.radius * bevelSide) : c;  // a bevel's sharp point
}

void placeNeedle(RigidBody& n, const MpmSetup& s, double depth, const Vec3& bevelSide, double speed) {
  n.bevelSide = bevelSide;
  n.point = needleTip(s, depth, bevelSide) + s.shift;
  n.velocity = speed * s.frame.axial;
  n.cutAhead = std::max(0.0, s.cutDepth - depth);  // parting "path": the pre-cut ahead of the tip
}

namespace {

// The lattice of the block (its spacing and offsets) kept inside the geometry's elements, each
// point with its element's material: layer, or inclusion (body 1 when it slides).
void addGeometryPoints(MpmSolver& solver, const Scenario& sc, const MpmSetup& s) {
  const TissueSpec& t = sc.tissue;
  const Lattice L(Vec3::Zero(), Vec3(t.length, t.width, t.height), sc.model.mpm.particle_spacing);
  std::vector<int> material = latticeRegions(*t.geometry, L, s.shift);
  std::vector<int> body(material.size(), 0);
  const auto layers = static_cast<int>(t.layers.size());
  for (std::size_t q = 0; q < material.size(); ++q)
    if (material[q] >= layers && t.inclusions[static_cast<std::size_t>(material[q] - layers)].sliding) body[q] = 1;
  solver.addLattice(L, material, body);
}

// The points inside each inclusion: a shape's take its material; a mesh group's have it already.
std::vector<std::vector<std::size_t>> inclusionMembers(MpmSolver& solver, const TissueSpec& t, const MpmSetup& s) {
  std::vector<std::vector<std::size_t>> members(t.inclusions.size());
  const std::size_t np = solver.size();
  for (std::size_t p = 0; p < np; ++p) {
    const int m = solver.material(p);
    if (m >= static_cast<int>(t.layers.size()) &&
        t.inclusions[static_cast<std::size_t>(m) - t.layers.size()].shape == InclusionSpec::Shape::Mesh) {
      members[static_cast<std::size_t>(m) - t.layers.size()].push_back(p);
      continue;
    }
    const Vec3 xc = solver.position(p) - s.shift;
    for (std::size_t i = t.inclusions.size(); i-- > 0;) {  // the last inclusion listed wins an overlap
      if (!t.inclusions[i].contains(xc.x(), xc.y(), xc.z())) continue;
      solver.reassign(p, static_cast<int>(t.layers.size() + i), t.inclusions[i].sliding ? 1 : 0);
      members[i].push_back(p);
      break;
    }
  }
  return members;
}

}  // namespace

std::vector<std::vector<std::size_t>> addTissue(MpmSolver& solver, const Scenario& sc, const MpmSetup& s) {
  const TissueSpec& t = sc.tissue;
  if (t.geometry) {
    addGeometryPoints(solver, sc, s);
  } else {
    double x = 0.0;
    for (std::size_t i = 0; i < t.layers.size(); ++i) {
      const double x1 = x + t.layers[i].thickness;
      solver.addBlock(Vec3(x, 0, 0), Vec3(x1, t.width, t.height), sc.model.mpm.particle_spacing,
                      static_cast<int>(i), 0);
      x = x1;
    }
  }
  auto members = inclusionMembers(solver, t, s);
  for (std::size_t i = 0; i < members.size(); ++i) {
    if (!members[i].empty()) continue;
    if (t.inclusions[i].shape == InclusionSpec::Shape::Mesh)
      throw refusal(sc, fmt::format("tissue.inclusions[{}].name", i), t.inclusions[i].name,
                    "its elements hold no material point (smaller than the particle spacing)",
                    fmt::format("a model.mpm.particle_spacing below the group's size ({:g} mm radius)",
                                t.inclusions[i].radius * 1e3));
    throw refusal(sc, fmt::format("tissue.inclusions[{}].radius", i),
                  fmt::format("{:g} mm", t.inclusions[i].radius * 1e3),
                  "holds no material point (smaller than the particle spacing)",
                  fmt::format("a radius of at least {:g} mm", sc.model.mpm.particle_spacing * 1e3));
  }
  return members;
}

}  // namespace needlesim::engines
