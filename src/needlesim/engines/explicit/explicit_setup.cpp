// Set-up of an explicit run (explicit_run.hpp): mesh and regions, seam or cohesive zone, solver, needle.
#include <algorithm>
#include <cmath>
#include <fmt/format.h>

#include "needlesim/core/error.hpp"
#include "needlesim/engines/explicit/explicit_run.hpp"
#include "needlesim/engines/explicit/path_needle.hpp"
#include "needlesim/engines/explicit/sleeve_setup.hpp"
#include "needlesim/materials/material_spec.hpp"
#include "needlesim/tissue/regions.hpp"

namespace needlesim::explicit_fe {

using Eigen::Vector3d;

namespace {

Vector3d centroid(const Mesh& m, int e) {
  const int npe = nodesPerElement(m.type);
  Vector3d c = Vector3d::Zero();
  for (int a = 0; a < npe; ++a)
    for (int i = 0; i < m.dim; ++i) c[i] += m.coord(m.conn[static_cast<std::size_t>(e) * npe + a], i) / npe;
  return c;
}

// Largest extent of an element's bounding box: its local size.
double elementSize(const Mesh& m, int e) {
  const int npe = nodesPerElement(m.type);
  Vector3d lo = Vector3d::Constant(1e300), hi = Vector3d::Constant(-1e300);
  for (int a = 0; a < npe; ++a)
    for (int i = 0; i < m.dim; ++i) {
      const double x = m.coord(m.conn[static_cast<std::size_t>(e) * npe + a], i);
      lo[i] = std::min(lo[i], x), hi[i] = std::max(hi[i], x);
    }
  double h = 0;
  for (int i = 0; i < m.dim; ++i) h = std::max(h, hi[i] - lo[i]);
  return h;
}

Vector3d nodePoint(const Mesh& m, int n) {
  Vector3d p = Vector3d::Zero();
  for (int i = 0; i < m.dim; ++i) p[i] = m.coord(n, i);
  return p;
}

// The grid lines of a graded list whose core [c - half, c + half] is replaced by uniform pieces: counts[k] equal
// elements between lines[k] and lines[k + 1].
std::vector<double> uniformCore(const std::vector<double>& graded, double c, double half,
                                const std::vector<double>& lines, const std::vector<int>& counts) {
  std::vector<double> z;
  for (double v : graded)
    if (v < c - half - 1e-12 || v > c + half + 1e-12) z.push_back(v);
  for (std::size_t k = 0; k < counts.size(); ++k)
    for (int i = 0; i <= counts[k]; ++i) z.push_back(lines[k] + (lines[k + 1] - lines[k]) * i / counts[k]);
  std::sort(z.begin(), z.end());
  z.erase(std::unique(z.begin(), z.end(), [](double a, double b) { return std::abs(a - b) < 1e-12; }), z.end());
  return z;
}

// Elements of at most h over a length (at least one).
int piecesOfAtMost(double length, double h) { return std::max(1, static_cast<int>(std::ceil(length / h - 1e-9))); }

// Grid lines across the slit (3D): the core [-half, half] of a graded list in uniform pieces with lines on the
// slit's fronts +-R, the slit itself split into ceil(2R / h) equal elements (never coarser than h), so the lip
// nodes sit at the same fractions of the needle's width on every mesh of a given count and their distance to
// the fronts falls steadily with h.
std::vector<double> slitCoordinates(const std::vector<double>& graded, double half, double R, double h) {
  const int outer = std::max(1, static_cast<int>(std::lround((half - R) / h)));
  return uniformCore(graded, 0.0, half, {-half, -R, R, half}, {outer, piecesOfAtMost(2.0 * R, h), outer});
}

// Grid lines normal to the slit (3D): the core [c - half, c + half] in uniform pieces of at most h either side of
// the slit's plane y, which runs through the bevel's sharp point.
std::vector<double> slitPlaneCoordinates(const std::vector<double>& graded, double c, double half, double y, double h) {
  return uniformCore(graded, c, half, {c - half, y, c + half},
                     {piecesOfAtMost(y - (c - half), h), piecesOfAtMost(c + half - y, h)});
}

}  // namespace

ExplicitRun::ExplicitRun(const Scenario& sc, ResultSink& sink)
    : sc_(sc),
      ex_(sc.model.explicit_fe),
      sink_(sink),
      frame_(needle::InsertionFrame::fromInsertion(sc.insertion)),
      shape_(needle::NeedleShape::fromSpec(sc.needle)),
      motion_(sc.insertion),
      dim_(sc.model.explicit_fe.dimension),
      inclusions_(sc.tissue.inclusions, frame_),
      markers_(sc.model.explicit_fe.dimension, [this](int node) {
        const auto& u = solver_->displacement();
        Vector3d d = Vector3d::Zero();
        for (int i = 0; i < dim_; ++i) d[i] = u[static_cast<std::size_t>(node) * dim_ + i];
        return d;
      }) {
  checkInput();
  // 2D plane strain shows only the in-plane sides of the bevel
  bevelSide_ = dim_ == 2 ? Vector3d(frame_.bevelSign() * frame_.lateral) : frame_.bevelSide();
  chooseSeam();
  buildMesh();
  solver_ = std::make_unique<ExplicitSolver>(mesh_, regionMaterials(), solverOptions());
  setupSeam();
  if (cohesive_) setupCohesive();
  fixDistalFace();
  setupNeedle();
  placeMarkers();
  createOutputs();
}

void ExplicitRun::checkInput() const {
  if (sc_.tissue.layers.empty()) throw Error("explicit: the tissue needs at least one layer");
  for (std::size_t i = 0; i < sc_.tissue.inclusions.size(); ++i)
    if (sc_.tissue.inclusions[i].sliding)
      throw InputError(sc_.where(fmt::format("tissue.inclusions[{}].interface", i)),
                       fmt::format("tissue.inclusions[{}].interface", i), "sliding",
                       "explicit: a sliding inclusion needs tissue-tissue contact, which explicit does not have",
                       "interface: bonded, or engine mpm");
  if (const auto& g = sc_.tissue.geometry; g && g->mesh->dim != dim_)
    throw InputError(sc_.where("tissue.geometry.file"), "tissue.geometry.file", g->file,
                     fmt::format("explicit: is a {}D mesh but model.explicit.dimension is {}d", g->mesh->dim, dim_),
                     fmt::format("model.explicit.dimension: {}d, or a {}D mesh", g->mesh->dim, dim_));
}

// The pre-cut seam runs through the leading point of the tip (the bevel's sharp point, at -R bevelSide)
// in 2D and 3D. In a generated 3D block it is a slit exactly as wide as the needle (|z| < R, its fronts
// on grid lines at z = +-R whatever the element size), whose lips the needle wedges open to its outline
// (cohesive_wedge.hpp bevelSlitWedge3D: the bevel face lifts the bevel-side lip, the wall-side lip stays):
// the displaced lip shape is the needle's at every node, so the load converges with the mesh instead of
// depending on which nodes happen to lie inside the needle (docs/models/explicit.md "Pre-cut slit (3D)").
void ExplicitRun::chooseSeam() {
  const double th = sc_.insertion.entry_angle, phi = sc_.insertion.bevel_orientation;
  const bool aligned = std::abs(th - 0.5 * M_PI) < 1e-9 && std::abs(std::sin(phi)) < 1e-9;
  seamOn_ = ex_.pre_cut && aligned;
  cohesive_ = ex_.cohesive.enable;
  // cylindrical sleeve seam (docs/models/cohesive.md "Sleeve seam"): its own O-grid block (sleeve_setup.hpp)
  sleeve_ = cohesive_ && ex_.cohesive.seam == "sleeve";
  // 3D bevel with the cohesive zone: through the needle axis instead (docs/models/cohesive.md "3D bevel"),
  // a plane through the point is tangent to the shaft and the needle would indent the tissue beside it.
  slit3d_ = seamOn_ && dim_ == 3 && !cohesive_ && !sc_.tissue.geometry;
  const bool seamThroughAxis = dim_ == 3 && cohesive_;
  seamY_ = sc_.insertion.entry_offset -
           (sc_.needle.tip == TipType::Bevel && !seamThroughAxis ? shape_.radius * bevelSide_.y() : 0.0);
}

void ExplicitRun::buildMesh() {
  dmax_ = std::min(sc_.tissue.length, sc_.maxDepth() + 2 * ex_.element_size);
  if (sleeve_) {
    sleeveMesh_ = sleeveMeshFor(sc_, shape_, sleeveRadius_);
    mesh_ = sleeveMesh_.mesh;
    seam_ = sleeveMesh_.pairs;
  } else if (sc_.tissue.geometry) {
    mesh_ = fromImportedGeometry(*sc_.tissue.geometry);
  } else {
    buildBlock();
  }
  if (dim_ == 2) thickness_ = 2 * shape_.radius;
  assignRegions();
  checkInclusionResolution();
  if (seamOn_ && !sleeve_) cutSeam();
  // crack path and follow-the-leader needle (path_from_scenario.hpp, docs/models/cohesive.md "Crack path")
  crackPath_ = setupCrackPath(sc_, shape_, seamY_, bevelSide_.y() >= 0 ? 1 : -1, seamOn_ && cohesive_, mesh_);
}

// The pre-cut seam along the needle path (splitSeam); through an imported geometry its nodes
// are first moved onto the seam (snapOntoSeam), the 3D strip as wide as the needle and the
// largest element edge that crosses the seam plane near the axis.
void ExplicitRun::cutSeam() {
  double halfWidth = slit3d_ ? shape_.radius : dim_ == 3 ? shape_.radius + 1.01 * ex_.element_size : 0.0;
  if (!sc_.tissue.geometry) {
    seam_ = splitSeam(mesh_, seamY_, 0.0, dmax_, halfWidth);
    if (slit3d_) requireNodesOnSlit();
    return;
  }
  if (dim_ == 3) halfWidth = shape_.radius + 1.01 * largestEdgeAcross(mesh_, seamY_, 2 * shape_.radius);
  const int moved = snapOntoSeam(mesh_, seamY_, 0.0, dmax_, halfWidth);
  seam_ = splitAlongFaces(mesh_, seamY_, 0.0, dmax_, halfWidth, bevelSide_.y() >= 0 ? 1 : -1);
  int off = 0;
  for (auto [a, b] : seam_) off += std::abs(mesh_.coord(a, 1) - seamY_) > 1e-12 ? 1 : 0;
  sink_.note(fmt::format("pre-cut seam through the imported mesh at y = {:.4g} mm: {} node pairs, {} nodes moved onto "
                         "it, {} left beside it on the side away from the needle",
                         seamY_ * 1e3, seam_.size(), moved, off));
}

// The slit must hold lip nodes inside the needle's section, else the needle would pass
// between the nodes and feel no tissue.
void ExplicitRun::requireNodesOnSlit() const {
  for (auto [a, b] : seam_)
    if (std::abs(mesh_.coord(a, 2)) < shape_.radius) return;
  throw InputError(sc_.where("model.explicit.element_size"), "model.explicit.element_size",
                   fmt::format("{:g} mm", ex_.element_size * 1e3),
                   fmt::format("explicit: no tissue node lies on the pre-cut slit across the needle (outer radius "
                               "{:g} mm): the needle would pass between the nodes without touching the tissue",
                               shape_.radius * 1e3),
                   fmt::format("an element size below the needle's outer diameter, {:g} mm", 2e3 * shape_.radius));
}

// Tissue block: depth x in [0, length] from the entry face, y across the width (needle path at
// y = entry_offset), z across the height (path at z = 0): the centred tissue frame.
void ExplicitRun::buildBlock() {
  const auto& t = sc_.tissue;
  const double y0 = sc_.insertion.entry_offset, h = ex_.element_size, H = ex_.max_element_size;
  const double half = 0.5 * ex_.core_width;
  // along the path: the core size down to just past the deepest tip position, then graded
  auto xs = gradedCoordinates(0.0, t.length, 0.0, std::max(dmax_, h), h, H, ex_.grading);
  auto ys = gradedCoordinates(-0.5 * t.width, 0.5 * t.width, y0 - half, y0 + half, h, H, ex_.grading);
  // the slit's plane through the sharp point, the core uniform either side of it
  if (slit3d_ && y0 - half > -0.5 * t.width && y0 + half < 0.5 * t.width && std::abs(seamY_ - y0) < half)
    ys = slitPlaneCoordinates(ys, y0, half, seamY_, h);
  else if (seamOn_)
    snapCoordinate(ys, seamY_);
  const ElementType type = elementTypeFromName(ex_.element.empty() ? (dim_ == 2 ? "quad4" : "hex8") : ex_.element);
  if (elementDim(type) != dim_)
    throw InputError(sc_.where("model.explicit.element"), "model.explicit.element", elementName(type),
                     "does not match dimension " + std::to_string(dim_) + "d",
                     dim_ == 2 ? "quad4 or tri3 in 2d" : "hex8 or tet4 in 3d");
  if (dim_ == 2) {
    mesh_ = structuredBlock(xs, ys, type);
  } else {
    auto zs = gradedCoordinates(-0.5 * t.height, 0.5 * t.height, -half, half, h, H, ex_.grading);
    if (slit3d_ && half > shape_.radius && half < 0.5 * t.height)  // the slit's fronts on the needle's outline
      zs = slitCoordinates(zs, half, shape_.radius, h);
    else if (slit3d_)
      for (double z : {-shape_.radius, shape_.radius}) snapCoordinate(zs, z);
    mesh_ = structuredBlock(xs, ys, zs, type);
  }
}

// Regions: layer r (stacked from the entry face, by element centroid; an imported geometry's
// regions come from its groups), then inclusion i as region layers + i (elements whose centroid
// lies inside a sphere or cylinder; a mesh inclusion is its group).
void ExplicitRun::assignRegions() {
  const auto& t = sc_.tissue;
  const int layers = static_cast<int>(t.layers.size());
  for (int e = 0; e < mesh_.elements(); ++e) {
    const Vector3d c = centroid(mesh_, e);
    const int r = tissue::regionAt(t, c.x(), c.y(), c.z());
    // an imported geometry's elements keep their group's layer unless an inclusion covers them
    if (!t.geometry || r >= layers) mesh_.region[e] = r;
  }
}

// Every inclusion needs elements, and resolving it needs about two elements across its radius.
void ExplicitRun::checkInclusionResolution() {
  const auto& incs = sc_.tissue.inclusions;
  const int layers = static_cast<int>(sc_.tissue.layers.size());
  std::vector<double> size(incs.size(), 0.0);
  std::vector<std::vector<char>> member(incs.size(), std::vector<char>(mesh_.nodes(), 0));
  const int npe = nodesPerElement(mesh_.type);
  for (int e = 0; e < mesh_.elements(); ++e) {
    const int i = mesh_.region[e] - layers;
    if (i < 0) continue;
    size[i] = std::max(size[i], elementSize(mesh_, e));
    for (int a = 0; a < npe; ++a) member[i][mesh_.conn[static_cast<std::size_t>(e) * npe + a]] = 1;
  }
  inclusionNodes_.assign(incs.size(), {});
  // An imported mesh is refined in its own file, a generated one by the explicit section.
  const std::string refine = sc_.tissue.geometry
                                 ? fmt::format("mesh it finer around the inclusion in {}", sc_.tissue.geometry->file)
                                 : std::string("refine model.explicit.element_size or core_width around it");
  for (std::size_t i = 0; i < incs.size(); ++i) {
    if (size[i] == 0.0)
      throw InputError(sc_.where(fmt::format("tissue.inclusions[{}].radius", i)),
                       fmt::format("tissue.inclusions[{}].radius", i), fmt::format("{:g} mm", incs[i].radius * 1e3),
                       fmt::format("explicit: inclusion '{}' contains no element centroid", incs[i].name),
                       sc_.tissue.geometry ? "a finer mesh there (in the geometry file) or a larger radius"
                                                 : "a finer mesh there (model.explicit.element_size, core_width) or a larger radius");
    for (int n = 0; n < mesh_.nodes(); ++n)
      if (member[i][n]) inclusionNodes_[i].push_back(n);
    if (incs[i].radius < 2.0 * size[i])
      sink_.warning(fmt::format("explicit: inclusion {} (radius {:g} mm) spans fewer than 2 elements of the local "
                                "size {:g} mm across its radius: its shape and stiffness are coarsely resolved; "
                                "{}.",
                                incs[i].name, incs[i].radius * 1e3, size[i] * 1e3, refine));
  }
}

std::vector<Material> ExplicitRun::regionMaterials() const {
  std::vector<Material> mats;
  for (const auto& r : tissue::regions(sc_.tissue)) mats.push_back(Material::fromSpec(r.material));
  return mats;
}

SolverOptions ExplicitRun::solverOptions() const {
  SolverOptions o;
  o.massScaling = ex_.mass_scaling;
  o.targetTimeStep = ex_.target_time_step;
  o.cfl = ex_.cfl;
  o.bulkViscosityLinear = ex_.bulk_viscosity_linear;
  o.bulkViscosityQuadratic = ex_.bulk_viscosity_quadratic;
  o.hourglass = ex_.hourglass;
  o.damping = ex_.damping;
  o.contactPenalty = ex_.contact_penalty;
  o.fixedContactStiffness = ex_.fixed_contact_stiffness;
  // Seam lips meet the sharp point with the offset the intact tissue ahead had (up to ~0.4 of a
  // core element at 0.5 mm, seed 004 example): allow one core element before stopping.
  if (seamOn_ || sleeve_) o.penetrationTolerance = ex_.element_size;
  return o;
}

// Seam pairs: tied until the tip arrives (node release) or joined by the cohesive zone; each lip
// meets the needle on its own side (needle::queryNeedle's `side`).
void ExplicitRun::setupSeam() {
  if (cohesive_ && !sleeve_ && (!seamOn_ || mesh_.type == ElementType::Tri3 || mesh_.type == ElementType::Tet4))
    throw InputError(sc_.where("model.explicit.cohesive"), "model.explicit.cohesive", "enable: true",
                     "needs the pre-cut seam of a quad4 (2d) or hex8 (3d) mesh",
                     "pre_cut: true, element quad4 or hex8 (generated, or an imported mesh of them), entry_angle 90 deg, "
                     "bevel_orientation 0 or 180 deg");
  if (cohesive_ && !sleeve_ && sc_.tissue.geometry) requireSeamOnPlane();
  // splitSeam gives the copies to the +y lip; the bevel faces +y when bevelSide.y > 0
  const int copySide = sleeve_ || bevelSide_.y() >= 0 ? 1 : -1;  // sleeve: core side -1, outer side +1
  // the slit's lips take the lip wedge, which first reaches a pair at the leading point, where it is released
  if (slit3d_) solver_->setWedgeLips(true);
  for (auto [a, b] : seam_) {
    const double z = mesh_.coord(a, 2);
    if (!cohesive_) solver_->addTie(a, b);
    // 3D: the lip sides disambiguate the nearest exit only on the sharp point's line (z = 0); off
    // it the tube's lower wall is the natural exit of the upper lip, which the side rule forbids
    // (node-release seam only: the cohesive wedge needs every lip's side, cohesive_wedge.hpp)
    if (dim_ == 3 && !cohesive_ && !slit3d_ && std::abs(z) > 0.5 * ex_.element_size) continue;
    solver_->setContactSide(a, -copySide);
    solver_->setContactSide(b, copySide);
  }
}

// The cohesive zone lies on the seam plane: through an imported mesh every seam pair must have been
// moved onto it (a node line, or plane, along the needle path), not left beside it.
void ExplicitRun::requireSeamOnPlane() const {
  int off = 0;
  for (auto [a, b] : seam_) off += std::abs(mesh_.coord(a, 1) - seamY_) > 1e-12 ? 1 : 0;
  if (off > 0)
    throw InputError(sc_.where("model.explicit.cohesive"), "model.explicit.cohesive", "enable: true",
                     fmt::format("explicit: {} of the {} seam node pairs through {} lie beside the seam plane y = {:.4g} mm, "
                                 "where the cohesive zone must lie",
                                 off, seam_.size(), sc_.tissue.geometry->file, seamY_ * 1e3),
                     "an imported mesh with a node line (2d) or plane (3d) along the needle path, e.g. a transfinite "
                     "band in the Gmsh script; or pre_cut without the cohesive zone");
}

// The cohesive law of a seam pair at x: G_c of the layer or inclusion there (or fracture_energy),
// K and t_c from the model's settings or that material's modulus (docs/models/cohesive.md).
CohesiveLaw ExplicitRun::cohesiveLawAt(const Vector3d& x) const {
  const auto& cs = ex_.cohesive;
  const auto regions = tissue::regions(sc_.tissue);
  const tissue::Region& region = regions[tissue::regionAt(sc_.tissue, x.x(), x.y(), x.z())];
  const std::string where = region.inclusion ? region.field : "layer " + region.name;
  const materials::MaterialSpec& material = region.material;
  const double toughness = region.toughness;
  if (!(cs.fracture_energy > 0) && !(toughness > 0))
    throw InputError(sc_.where("model.explicit.cohesive"), "model.explicit.cohesive.fracture_energy", "0",
                     "explicit: " + where + ".toughness is not given, and the cohesive zone through it needs G_c",
                     "a toughness in " + where + ", or model.explicit.cohesive.fracture_energy > 0");
  const auto mod = materials::smallStrainModuli(material);
  const double E = mod.youngs(), nu = mod.poisson(), Ep = E / (1 - nu * nu);
  CohesiveLaw law;
  law.energy = cs.fracture_energy > 0 ? cs.fracture_energy : toughness;
  law.shearEnergy = cs.mode_ii_ratio * law.energy;
  law.strength = cs.strength > 0 ? cs.strength : 2.0 * law.energy / cs.critical_separation;
  law.stiffness = cs.stiffness > 0                ? cs.stiffness
                  : cs.constitutive_thickness > 0 ? E / cs.constitutive_thickness
                                                  : 10.0 * Ep / ex_.element_size;
  try {
    law.validate();
  } catch (const Error& e) {
    throw InputError(sc_.where("model.explicit.cohesive"), "model.explicit.cohesive", where, e.what(),
                     "strength, stiffness and G_c (fracture_energy or the toughness) that make a bilinear law");
  }
  return law;
}

// Cohesive zone on the seam pairs instead of node release (docs/models/cohesive.md).
void ExplicitRun::setupCohesive() {
  cohGc_.assign(mesh_.nodes(), 0.0);
  for (auto [a, b] : seam_) {
    (void)b;
    cohLaws_.push_back(cohesiveLawAt(nodePoint(mesh_, a)));
    cohGc_[a] = cohLaws_.back().energy;
  }
  if (dim_ == 3) {
    // quadrilaterals on the seam plane y = seamY (cohesive_surface.cpp); the faces reaching the
    // unsplit nodes beyond the strip carry the closed crack front
    solver_->setCohesive(sleeve_ ? CohesiveInterface::fromQuads(mesh_, seam_, cohLaws_, sleeveMesh_.quads,
                                                                sleeveMesh_.quadNormals, frame_.axial)
                                 : CohesiveInterface::surface3D(mesh_, seam_, cohLaws_, Vector3d::UnitY(), frame_.axial));
    if (sleeve_) solver_->setSleeveRadius(sleeveRadius_);
    return;
  }
  CohesiveInterface ci(mesh_.X, seam_, cohLaws_, Eigen::Vector2d::UnitX(), 1.0);
  // closed crack tip: the shared node beyond the seam's last pair
  double xLast = -1e300, xNext = 1e300;
  for (auto [a, b] : seam_) xLast = std::max(xLast, mesh_.coord(a, 0));
  for (int n = 0; n < mesh_.nodes(); ++n)
    if (std::abs(mesh_.coord(n, 1) - crackPath_.seamHeight(mesh_.coord(n, 0), seamY_)) < 1e-9 &&
        mesh_.coord(n, 0) > xLast + 1e-12)
      xNext = std::min(xNext, mesh_.coord(n, 0));
  if (xNext < 1e299) ci.addEndLength(0.0, 0.5 * (xNext - xLast));
  solver_->setCohesive(std::move(ci));
}

// Distal face fixed (seed 001 section 3.2); an imported geometry's far side (ImportedGeometry::supported).
void ExplicitRun::fixDistalFace() {
  const int fixed = solver_->addGroup();
  const auto& g = sc_.tissue.geometry;
  for (int n = 0; n < mesh_.nodes(); ++n)
    if (g ? n < static_cast<int>(g->supported.size()) && g->supported[n] : mesh_.coord(n, 0) > sc_.tissue.length - 1e-9)
      for (int i = 0; i < dim_; ++i) solver_->addDof(fixed, n, i);
}

// Wall friction per tissue node: the mean of its elements' layer or inclusion coefficients; empty
// when one coefficient holds everywhere.
std::vector<double> ExplicitRun::wallFrictionPerNode() const {
  const auto regions = tissue::regions(sc_.tissue);
  if (tissue::uniformFriction(regions)) return {};
  const std::vector<double> mu = tissue::regionFrictions(regions);
  const Mesh& m = solver_->mesh();
  const int npe = nodesPerElement(m.type);
  std::vector<double> sum(m.nodes(), 0.0), count(m.nodes(), 0.0);
  for (int e = 0; e < m.elements(); ++e)
    for (int a = 0; a < npe; ++a) {
      const int n = m.conn[static_cast<std::size_t>(e) * npe + a];
      sum[n] += mu[m.region[e]];
      count[n] += 1.0;
    }
  for (int n = 0; n < m.nodes(); ++n) sum[n] /= count[n];
  return sum;
}

void ExplicitRun::setupNeedle() {
  RigidNeedle nd;
  nd.shape = shape_;
  nd.pose.axis = frame_.axial;
  nd.pose.bevelSide = bevelSide_;
  nd.pose.tip = frame_.onAxis(motion_.at(0.0).depth);
  nd.frictionWall = sc_.tissue.layers.front().friction.coefficient;
  nd.frictionWallNode = wallFrictionPerNode();
  nd.frictionTip = ex_.tip_friction;
  if (crackPath_.path) {
    nd.path = crackPath_.path;
    nd.pathSide = crackPath_.side;
    placeOnPath(nd, motion_.at(0.0).depth);
  }
  solver_->setNeedle(nd);
  // Deformable needle (model.explicit.needle_model: beam, deformable_needle.hpp): a cantilever clamped at
  // the base, which follows the profile; it sets the contact pose from its deflection each step.
  if (ex_.needle_model == "beam")
    beam_ = std::make_unique<DeformableNeedle>(
        needle::Section{sc_.needle.youngs_modulus, sc_.needle.outer_diameter, sc_.needle.inner_diameter},
        shape_.length, dim_);
}

}  // namespace needlesim::explicit_fe
