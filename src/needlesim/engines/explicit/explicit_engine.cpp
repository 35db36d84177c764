#include "needlesim/engines/explicit/explicit_engine.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <memory>

#include "needlesim/core/error.hpp"
#include "needlesim/core/progress.hpp"
#include "needlesim/engines/explicit/contact_output.hpp"
#include "needlesim/engines/explicit/deformable_needle.hpp"
#include "needlesim/engines/explicit/pain_index.hpp"
#include "needlesim/engines/explicit/path_from_scenario.hpp"
#include "needlesim/engines/explicit/path_needle.hpp"
#include "needlesim/engines/explicit/sleeve_setup.hpp"
#include "needlesim/engines/explicit/solver.hpp"
#include "needlesim/insertion/motion_profile.hpp"
#include "needlesim/materials/material_spec.hpp"
#include "needlesim/io/field_series.hpp"

#ifdef _OPENMP
#include <omp.h>
#endif

namespace needlesim::engines {

using namespace explicit_fe;
using Eigen::Vector3d;

namespace {

struct Setup {
  Mesh mesh;
  std::vector<std::pair<int, int>> seam;
  double thickness = 1.0;  // m, out-of-plane extent of a 2D model
};

// Tissue block: depth x in [0, length] from the entry face, y across the width
// (needle path at y = entry_offset), z across the height (path at z = 0).
Setup buildMesh(const Scenario& sc, const ExplicitModelSpec& ex, const needle::NeedleShape& shape, double seamY,
                bool seamOn) {
  Setup s;
  const auto& t = sc.tissue;
  if (!ex.mesh.empty()) {
    std::filesystem::path p = ex.mesh;
    if (p.is_relative() && !sc.source.empty() && sc.source[0] != '<')
      p = std::filesystem::path(sc.source).parent_path() / p;
    s.mesh = readGmsh(p.string());
    return s;
  }
  const double y0 = sc.insertion.entry_offset, h = ex.element_size, H = ex.max_element_size;
  const double half = 0.5 * ex.core_width;
  // along the path: the core size down to just past the deepest tip position, then graded
  const double dmax = std::min(t.length, sc.maxDepth() + 2 * h);
  auto xs = gradedCoordinates(0.0, t.length, 0.0, std::max(dmax, h), h, H, ex.grading);
  auto ys = gradedCoordinates(-0.5 * t.width, 0.5 * t.width, y0 - half, y0 + half, h, H, ex.grading);
  if (seamOn) snapCoordinate(ys, seamY);
  const ElementType type = elementTypeFromName(ex.element.empty() ? (ex.dimension == 2 ? "quad4" : "hex8") : ex.element);
  if (elementDim(type) != ex.dimension)
    throw Error("model.explicit.element " + elementName(type) + " does not match dimension " +
                std::to_string(ex.dimension) + "d");
  if (ex.dimension == 2) {
    s.mesh = structuredBlock(xs, ys, type);
    s.thickness = 2 * shape.radius;
  } else {
    auto zs = gradedCoordinates(-0.5 * t.height, 0.5 * t.height, -half, half, h, H, ex.grading);
    s.mesh = structuredBlock(xs, ys, zs, type);
  }
  // layers stacked from the entry face
  double edge = 0;
  std::vector<double> ends;
  for (const auto& l : t.layers) ends.push_back(edge += l.thickness);
  const int d = s.mesh.dim, npe = nodesPerElement(s.mesh.type);
  for (int e = 0; e < s.mesh.elements(); ++e) {
    double cx = 0;
    for (int a = 0; a < npe; ++a) cx += s.mesh.coord(s.mesh.conn[e * npe + a], 0) / npe;
    int r = 0;
    while (r + 1 < static_cast<int>(ends.size()) && cx > ends[r]) ++r;
    s.mesh.region[e] = r;
  }
  (void)d;
  if (seamOn) s.seam = splitSeam(s.mesh, seamY, 0.0, dmax, ex.dimension == 3 ? shape.radius + 1.01 * h : 0.0);
  return s;
}

io::CellType cellType(ElementType t) {
  switch (t) {
    case ElementType::Quad4: return io::CellType::Quad;
    case ElementType::Tri3: return io::CellType::Triangle;
    case ElementType::Hex8: return io::CellType::Hexa;
    case ElementType::Tet4: return io::CellType::Tetra;
  }
  return io::CellType::Quad;
}

}  // namespace

void runExplicit(const Scenario& sc, ResultSink& sink, const RunOptions& options) {
  const ExplicitModelSpec& ex = sc.model.explicit_fe;
#ifdef _OPENMP
  if (ex.threads > 0) omp_set_num_threads(ex.threads);
#endif
  if (sc.tissue.layers.empty()) throw Error("explicit: the tissue needs at least one layer");
  const auto shape = needle::NeedleShape::fromSpec(sc.needle);
  const int dim = ex.dimension;
  // Needle frame (insertion plane x-y): axis at entry_angle to the entry face.
  const double th = sc.insertion.entry_angle;
  const Vector3d axis(std::sin(th), -std::cos(th), 0.0);
  const Vector3d e1(-axis.y(), axis.x(), 0.0), e2 = Vector3d::UnitZ();
  const double phi = sc.insertion.bevel_orientation;
  const Vector3d bevelSide = dim == 2 ? Vector3d((std::cos(phi) >= 0 ? 1.0 : -1.0) * e1) : Vector3d(std::cos(phi) * e1 + std::sin(phi) * e2);
  const Vector3d entry(0.0, sc.insertion.entry_offset, 0.0);
  // The pre-cut seam runs through the leading point of the tip (the bevel's sharp point).
  const bool aligned = std::abs(th - 0.5 * M_PI) < 1e-9 && std::abs(std::sin(phi)) < 1e-9;
  const bool seamOn = ex.pre_cut && ex.mesh.empty() && aligned;
  // 3D bevel with the cohesive zone: through the needle axis instead (docs/models/cohesive.md "3D bevel"),
  // a plane through the point is tangent to the shaft and the needle would indent the tissue beside it.
  const bool seamThroughAxis = dim == 3 && ex.cohesive.enable;
  const double seamY = sc.insertion.entry_offset - (sc.needle.tip == TipType::Bevel && !seamThroughAxis
                                                        ? shape.radius * bevelSide.y()
                                                        : 0.0);
  // cylindrical sleeve seam (docs/models/cohesive.md "Sleeve seam"): its own O-grid block (sleeve_setup.hpp)
  const bool sleeve = ex.cohesive.enable && ex.cohesive.seam == "sleeve";
  double sleeveR = 0.0;
  SleeveMesh sm;
  Setup st;
  if (sleeve) {
    sm = sleeveMeshFor(sc, shape, sleeveR);
    st.mesh = sm.mesh;
    st.seam = sm.pairs;
  } else {
    st = buildMesh(sc, ex, shape, seamY, seamOn);
  }
  // crack path and follow-the-leader needle (path_from_scenario.hpp, docs/models/cohesive.md "Crack path")
  const CrackPathSetup cpath = setupCrackPath(sc, shape, seamY, bevelSide.y() >= 0 ? 1 : -1,
                                              seamOn && ex.cohesive.enable, st.mesh);

  std::vector<Material> mats;
  for (const auto& l : sc.tissue.layers) mats.push_back(Material::fromSpec(l.material));
  SolverOptions o;
  o.massScaling = ex.mass_scaling;
  o.targetTimeStep = ex.target_time_step;
  o.cfl = ex.cfl;
  o.bulkViscosityLinear = ex.bulk_viscosity_linear;
  o.bulkViscosityQuadratic = ex.bulk_viscosity_quadratic;
  o.hourglass = ex.hourglass;
  o.damping = ex.damping;
  o.contactPenalty = ex.contact_penalty;
  o.fixedContactStiffness = ex.fixed_contact_stiffness;
  // Seam lips meet the sharp point with the offset the intact tissue ahead had (up to ~0.4 of a
  // core element at 0.5 mm, seed 004 example): allow one core element before stopping.
  if (seamOn || sleeve) o.penetrationTolerance = ex.element_size;
  const Mesh meshCopy = st.mesh;
  ExplicitSolver solver(std::move(st.mesh), mats, o);
  // splitSeam gives the copies to the +y lip; the bevel faces +y when bevelSide.y > 0
  const int copySide = sleeve || bevelSide.y() >= 0 ? 1 : -1;  // sleeve: core side -1, outer side +1
  const auto& cs = ex.cohesive;
  const bool cohOn = cs.enable;
  if (cohOn && !sleeve && (!seamOn || meshCopy.type == ElementType::Tri3 || meshCopy.type == ElementType::Tet4))
    throw Error("model.explicit.cohesive needs the pre-cut seam of a quad4 (2d) or hex8 (3d) mesh (pre_cut: true, no "
                "imported mesh, entry_angle 90 deg, bevel_orientation 0 or 180 deg)");
  for (auto [a, b] : st.seam) {
    if (!cohOn) solver.addTie(a, b);
    // 3D: the lip sides disambiguate the nearest exit only on the sharp point's line (z = 0); off
    // it the tube's lower wall is the natural exit of the upper lip, which the side rule forbids
    // (node-release seam only: the cohesive wedge needs every lip's side, cohesive_wedge.hpp)
    if (dim == 3 && !cohOn && std::abs(meshCopy.coord(a, 2)) > 0.5 * ex.element_size) continue;
    solver.setContactSide(a, -copySide);
    solver.setContactSide(b, copySide);
  }
  // Cohesive zone on the seam pairs instead of node release (docs/models/cohesive.md).
  double cohGcArea = 0.0;  // sum G_c x tributary length over the pairs the tip passed (J/m), set in record
  std::vector<CohesiveLaw> cohLaws;
  std::vector<double> cohGc;  // per node: G_c of its pair (the interface sorts the pairs)
  if (cohOn) {
    double edgeX = 0;
    std::vector<double> ends;
    for (const auto& l : sc.tissue.layers) ends.push_back(edgeX += l.thickness);
    for (auto [a, b] : st.seam) {
      (void)b;
      const double x = meshCopy.coord(a, 0);
      int r = 0;
      while (r + 1 < static_cast<int>(ends.size()) && x > ends[r]) ++r;
      const auto& layer = sc.tissue.layers[r];
      const auto mod = materials::smallStrainModuli(layer.material);
      const double E = mod.youngs(), nu = mod.poisson(), Ep = E / (1 - nu * nu);
      CohesiveLaw law;
      law.energy = cs.fracture_energy > 0 ? cs.fracture_energy : layer.toughness;
      law.shearEnergy = cs.mode_ii_ratio * law.energy;
      law.strength = cs.strength > 0 ? cs.strength : 2.0 * law.energy / cs.critical_separation;
      law.stiffness = cs.stiffness > 0                ? cs.stiffness
                      : cs.constitutive_thickness > 0 ? E / cs.constitutive_thickness
                                                      : 10.0 * Ep / ex.element_size;
      try {
        law.validate();
      } catch (const Error& e) {
        throw Error(std::string("model.explicit.cohesive (layer ") + layer.name + "): " + e.what());
      }
      cohLaws.push_back(law);
      if (cohGc.empty()) cohGc.assign(meshCopy.nodes(), 0.0);
      cohGc[a] = law.energy;
    }
    if (dim == 3) {
      // quadrilaterals on the seam plane y = seamY (cohesive_surface.cpp); the faces reaching the
      // unsplit nodes beyond the strip carry the closed crack front
      solver.setCohesive(sleeve ? CohesiveInterface::fromQuads(meshCopy, st.seam, cohLaws, sm.quads, sm.quadNormals, axis)
                                : CohesiveInterface::surface3D(meshCopy, st.seam, cohLaws, Vector3d::UnitY(), axis));
      if (sleeve) solver.setSleeveRadius(sleeveR);
    } else {
      CohesiveInterface ci(meshCopy.X, st.seam, cohLaws, Eigen::Vector2d::UnitX(), 1.0);
      // closed crack tip: the shared node beyond the seam's last pair
      double xLast = -1e300, xNext = 1e300;
      for (auto [a, b] : st.seam) xLast = std::max(xLast, meshCopy.coord(a, 0));
      for (int n = 0; n < meshCopy.nodes(); ++n)
        if (std::abs(meshCopy.coord(n, 1) - cpath.seamHeight(meshCopy.coord(n, 0), seamY)) < 1e-9 &&
            meshCopy.coord(n, 0) > xLast + 1e-12)
          xNext = std::min(xNext, meshCopy.coord(n, 0));
      if (xNext < 1e299) ci.addEndLength(0.0, 0.5 * (xNext - xLast));
      solver.setCohesive(std::move(ci));
    }
  }
  // Distal face fixed (seed 001 section 3.2).
  const int fixed = solver.addGroup();
  for (int n = 0; n < meshCopy.nodes(); ++n)
    if (meshCopy.coord(n, 0) > sc.tissue.length - 1e-9)
      for (int i = 0; i < dim; ++i) solver.addDof(fixed, n, i);

  MotionProfile motion(sc.insertion);
  RigidNeedle nd;
  nd.shape = shape;
  nd.pose.axis = axis;
  nd.pose.bevelSide = bevelSide;
  nd.pose.tip = entry + motion.at(0.0).depth * axis;
  nd.frictionWall = sc.tissue.layers.front().friction.coefficient;
  nd.frictionTip = ex.tip_friction;
  if (cpath.path) {
    nd.path = cpath.path;
    nd.pathSide = cpath.side;
    placeOnPath(nd, motion.at(0.0).depth);
  }
  solver.setNeedle(nd);
  // Deformable needle (model.explicit.needle_model: beam, deformable_needle.hpp): a cantilever clamped at
  // the base, which follows the profile; it sets the contact pose from its deflection each step.
  std::unique_ptr<DeformableNeedle> beam;
  if (ex.needle_model == "beam")
    beam = std::make_unique<DeformableNeedle>(
        needle::Section{sc.needle.youngs_modulus, sc.needle.outer_diameter, sc.needle.inner_diameter}, shape.length, dim);

  const double T = motion.duration();
  const double thick = dim == 2 ? st.thickness : 1.0;
  const double outDt = sc.output.interval > 0 ? sc.output.interval : T / 500.0;
  const double fieldDt = ex.field_interval > 0 ? ex.field_interval : T / 20.0;
  const double depth0 = motion.at(0.0).depth;

  io::Table series({{"time", "s"}, {"depth", "m"}, {"needle displacement", "m"}, {"force", "N"},
                    {"lateral force", "N"}, {"tip force", "N"}, {"moment", "N m"}, {"contact nodes", "1"},
                    {"kinetic energy", "J"}, {"internal energy", "J"}, {"strain energy", "J"},
                    {"hourglass energy", "J"}, {"external work", "J"}, {"contact work", "J"},
                    {"energy balance", "J"}, {"kinetic/internal", "1"}, {"time step", "s"}, {"open seam nodes", "1"},
                    {"cohesive stored energy", "J"}, {"cohesive dissipation", "J"}, {"cracked length", "m"},
                    {"cracked area", "m^2"}, {"needle work", "J"}, {"friction dissipation", "J"},
                    {"penalty energy", "J"}, {"needle energy balance", "J"}, {"tip lateral force", "N"},
                    {"contact area", "m^2"}, {"mean contact pressure", "Pa"}, {"max contact pressure", "Pa"},
                    {"entry-frame lateral force", "N"}, {"axial torque", "N m"}, {"bevel orientation", "rad"},
                    {"tip deflection", "m"}, {"tip slope", "rad"}, {"beam tip deflection", "m"}});
  double peakTorque = 0;
  ContactOutput contactOut(solver.mesh());  // contact pressure and area (contact_output.hpp)
  double peakArea = 0, peakPressure = 0;
  io::FieldSeries* fields = sink.fields("tissue", dim);
  io::FieldSeries* needleFields = sink.fields("needle", dim);
  if (fields) {
    const int npe = nodesPerElement(meshCopy.type);
    std::vector<int> conn(solver.mesh().conn.begin(), solver.mesh().conn.end());
    (void)npe;
    fields->setMesh(meshCopy.X, cellType(meshCopy.type), conn);
  }
  auto needleSurface = [&]() {
    auto* n = solver.needle();
    if (n->path) return pathNeedleOutline2D(*n);
    return dim == 2 ? needle::needleOutline2D(n->shape, n->pose) : needle::needleSurface3D(n->shape, n->pose, 24, 4);
  };
  if (needleFields) {
    auto s = needleSurface();
    std::vector<double> pts;
    for (std::size_t i = 0; i < s.points.size() / 3; ++i)
      for (int k = 0; k < dim; ++k) pts.push_back(s.points[3 * i + k]);
    needleFields->setMesh(pts, dim == 2 ? io::CellType::Line : io::CellType::Triangle, s.cells);
  }
  std::vector<double> sig, vm, ls, J, xcur;
  auto writeFields = [&]() {
    if (fields) {
      const auto& u = solver.displacement();
      xcur.resize(u.size());
      for (std::size_t k = 0; k < u.size(); ++k) xcur[k] = meshCopy.X[k] + u[k];
      solver.cellFields(sig, vm, ls, J);
      fields->beginStep(solver.time());
      fields->stepPoints(xcur);
      fields->pointData("displacement", u, dim);
      fields->pointData("velocity", solver.velocity(), dim);
      contactOut.update(solver);
      fields->pointData("contact_pressure", contactOut.pressure(), 1);
      fields->cellData("cauchy_stress", sig, 6);
      fields->cellData("von_mises", vm, 1);
      fields->cellData("log_strain", ls, 6);
      fields->cellData("J", J, 1);
      fields->endStep();
    }
    if (needleFields) {
      auto s = needleSurface();
      std::vector<double> pts;
      for (std::size_t i = 0; i < s.points.size() / 3; ++i)
        for (int k = 0; k < dim; ++k) pts.push_back(s.points[3 * i + k]);
      needleFields->beginStep(solver.time());
      needleFields->stepPoints(pts);
      needleFields->endStep();
    }
  };

  // Cracked length: 2D the fully damaged seam length; 3D its extent along the path (the area is reported apart).
  auto crackedLength = [&]() {
    const auto* c = solver.cohesive();
    if (dim == 2) return c->crackedLength();
    double lo = 1e300, hi = -1e300;
    for (int p = 0; p < c->pairs(); ++p)
      if (c->state(p).damage >= 1.0) lo = std::min(lo, c->position(p)), hi = std::max(hi, c->position(p));
    return hi >= lo ? hi - lo : 0.0;
  };
  double peak = 0, ratioMax = 0, balanceMax = 0, energyScale = 1e-300, needleBalanceMax = 0, needleWorkMax = 1e-300;
  auto record = [&]() {
    const auto* n = solver.needle();
    const auto& E = solver.energies();
    // a path needle: depth = arc length of the tip, axial force = the reaction along the local tangents,
    // tip and lateral forces in the tip's frame
    const double depth = n->path ? n->station : (n->pose.tip - entry).dot(axis);
    const double fAx = (n->path ? -n->driveForce : -n->force.dot(axis)) * thick, fLat = n->force.dot(n->pose.bevelSide) * thick;
    const double tip = -n->tipForce.dot(n->path ? n->pose.axis : axis) * thick;
    const double ie = E.internal;
    const double ratio = ie > 0 ? E.kinetic / ie : 0.0;
    energyScale = std::max({energyScale, std::abs(ie), std::abs(E.externalWork), std::abs(E.contactWork), E.kinetic});
    if (solver.time() > 0.1 * T) ratioMax = std::max(ratioMax, ratio);
    balanceMax = std::max(balanceMax, std::abs(E.balance()));
    peak = std::max(peak, fAx);
    // torque the tissue applies about the needle axis (the base must hold -torque)
    const double torque = n->moment.dot(axis) * thick;
    if (std::abs(torque) > std::abs(peakTorque)) peakTorque = torque;
    contactOut.update(solver);
    const double cArea = contactOut.contactArea() * thick;
    peakArea = std::max(peakArea, cArea);
    peakPressure = std::max(peakPressure, contactOut.maxPressure());
    series.addRow({solver.time(), depth, depth - depth0, fAx, fLat, tip, n->moment.z() * thick,
                   static_cast<double>(n->nodesInContact), E.kinetic * thick, ie * thick, E.strain * thick,
                   E.hourglass * thick, E.externalWork * thick, E.contactWork * thick, E.balance() * thick, ratio,
                   solver.timeStep(),
                   static_cast<double>(cohOn ? solver.cohesive()->fullyDamaged()
                                             : static_cast<int>(st.seam.size()) - solver.activeTies()),
                   E.cohesiveStored * thick, E.cohesiveDissipated * thick,
                   cohOn ? crackedLength() : 0.0, cohOn ? solver.cohesive()->crackedLength() * (dim == 2 ? thick : 1.0) : 0.0,
                   E.needleWork * thick, E.frictionDissipation * thick, E.penaltyEnergy * thick,
                   E.balanceWithNeedle() * thick, n->tipForce.dot(n->pose.bevelSide) * thick, cArea,
                   contactOut.meanPressure(), contactOut.maxPressure(), n->force.dot(e1) * thick, torque,
                   std::atan2(n->pose.bevelSide.dot(e2), n->pose.bevelSide.dot(e1)),
                   beam ? beam->tipDeflection() : 0.0, beam ? beam->tipSlope() : 0.0,
                   beam ? beam->targetDeflection() : 0.0});
    needleBalanceMax = std::max(needleBalanceMax, std::abs(E.balanceWithNeedle()));
    needleWorkMax = std::max(needleWorkMax, std::abs(E.needleWork));
    if (cohOn) {
      const auto* c = solver.cohesive();
      cohGcArea = 0.0;
      for (int p = 0; p < c->pairs(); ++p)
        if (c->state(p).damage >= 1.0 - 1e-12) cohGcArea += cohGc[c->node(p, 0)] * c->tributaryLength(p) * thick;
    }
  };
  auto flush = [&](const std::string& status) {
    sink.table("explicit", series);
    const auto disp = series.column("needle displacement"), force = series.column("force"),
               time = series.column("time");
    std::vector<double> dmm, tms;
    for (double v : disp) dmm.push_back(v * 1e3);
    io::Plot fp{"Needle force against needle displacement", "needle displacement [mm]", "force [N]", {}};
    fp.series.push_back({"axial force (reaction at the base)", dmm, force});
    fp.series.push_back({"tip surface", dmm, series.column("tip force"), false, true});
    sink.plot(fp);
    io::Plot ep{"Energies", "time [s]", "energy [J]", {}};
    for (const char* c : {"kinetic energy", "internal energy", "external work", "contact work", "energy balance"})
      ep.series.push_back({c, time, series.column(c)});
    if (cohOn) ep.series.push_back({"cohesive dissipation", time, series.column("cohesive dissipation")});
    sink.plot(ep);
    sink.result("peak_force", peak, "N", "largest axial needle force (reaction at the base)");
    sink.result("final_force", force.empty() ? 0.0 : force.back(), "N", "axial needle force at the end");
    sink.result("kinetic_internal_ratio_max", ratioMax, "1",
                "largest kinetic / internal energy after the first 10 % (quasi-static if < 0.05-0.1)");
    sink.result("energy_balance_error", balanceMax / energyScale, "1",
                "largest |energy balance| / largest energy term");
    {
      const auto& E = solver.energies();
      sink.result("needle_work", E.needleWork * thick, "J", "work done by the moving needle (its reaction x its travel)");
      sink.result("friction_dissipation", E.frictionDissipation * thick, "J", "Coulomb friction force x slip on the needle");
      sink.result("penalty_energy", E.penaltyEnergy * thick, "J", "energy stored in the needle contact penalty at the end");
      sink.result("viscous_dissipation", (E.internal - E.strain - E.hourglass) * thick, "J",
                  "internal work less strain and hourglass energy (bulk viscosity, viscoelasticity)");
      sink.result("needle_energy_balance_error", needleBalanceMax / needleWorkMax, "1",
                  "largest |needle work - kinetic - internal - cohesive - friction - penalty| / largest needle work");
    }
    sink.result("peak_contact_area", peakArea, "m^2",
                "largest needle-tissue contact area (nodal tributary areas; 2D: times the slab thickness)");
    sink.result("max_contact_pressure", peakPressure, "Pa", "largest nodal needle-tissue contact pressure");
    sink.result("peak_axial_torque", peakTorque, "N m", "largest tissue torque about the needle axis (rotation)");
    if (beam) {
      sink.result("final_tip_deflection", beam->tipDeflection(), "m",
                  "lateral tip deflection of the deformable needle at the end, + towards the bevel side");
      sink.result("final_tip_slope", beam->tipSlope(), "rad", "tip slope of the deformable needle at the end");
      sink.result("needle_coupling_residual_mean", beam->meanResidual(), "m",
                  "mean |beam tip deflection under the last step's loads - applied (followed) deflection| in contact");
      sink.note("Deformable needle (needle_model: beam): Euler-Bernoulli cantilever clamped at the base, EI = " +
                std::to_string(beam->EI()) + " N m^2, loaded by the contact resultant each step; the contact "
                "surface is a straight needle along the deflected tip axis (docs/models/explicit.md).");
    }
    sink.result("elements", solver.mesh().elements(), "1", "elements");
    sink.result("steps", static_cast<double>(solver.steps()), "1", "time steps");
    sink.result("time_step", solver.timeStep(), "s", "last stable time step (after mass scaling)");
    sink.result("added_mass", solver.totalMass() / solver.physicalMass() - 1.0, "1", "mass added by mass scaling / physical mass");
    // Needle forces split as seed 004 Fig 8: P, Q on the tip (bevel) faces, q_x, q_y on the wall,
    // F_x = P + q_x, F_y = Q + q_y (axial, lateral towards the bevel side); seed 001's pain index.
    const auto tipAx = series.column("tip force"), tipLat = series.column("tip lateral force");
    if (!tipAx.empty()) {
      sink.result("tip_force_axial", tipAx.back(), "N", "P: axial force on the tip (bevel) faces at the end; F_x = P + q_x (seed 004)");
      sink.result("tip_force_lateral", tipLat.back(), "N",
                  "Q: lateral force on the tip (bevel) faces at the end, + towards the bevel side; F_y = Q + q_y (seed 004)");
      sink.result("peak_tip_force_axial", *std::max_element(tipAx.begin(), tipAx.end()), "N",
                  "largest axial force on the tip faces");
      // seed 004 Fig 13: P, Q on the bevel (tip faces), q_x, q_y on the rest of the needle (wall)
      sink.result("wall_force_axial", force.back() - tipAx.back(), "N", "q_x: axial force on the needle wall at the end");
      sink.result("wall_force_lateral", series.column("lateral force").back() - tipLat.back(), "N",
                  "q_y: lateral force on the needle wall at the end, + towards the bevel side");
    }
    if (dim == 3) {
      const auto pdi = painIndex(time, force, needleAnnulusArea(sc.needle.outer_diameter, sc.needle.inner_diameter),
                                 painBasicStress(sc.tissue.layers.front().material));
      sink.result("pain_index_peak", pdi.peak, "1", "PDI = F / (pi (R^2 - r^2)) / sigma*(0.3 strain), peak (seed 001 eqs 7-8)");
      sink.result("pain_index_mean", pdi.mean, "1", "PDI averaged over the insertion time (seed 001 eqs 7-8)");
      sink.result("pain_basic_stress", pdi.basicStress, "Pa", "sigma*: tissue stress at 0.3 compressive strain");
    }
    if (dim == 2)
      sink.note("2D plane strain: forces and energies are per metre of thickness times the needle diameter (" +
                std::to_string(thick * 1e3) + " mm), i.e. a slab as thick as the needle.");
    if (cohOn) {
      const auto* c = solver.cohesive();
      const auto& E = solver.energies();
      sink.result("cohesive_dissipation", E.cohesiveDissipated * thick, "J",
                  "energy dissipated by the cohesive zone (slab as thick as the needle in 2D)");
      sink.result("cohesive_stored", E.cohesiveStored * thick, "J", "elastic energy stored in the cohesive zone");
      sink.result("cracked_length", crackedLength(), "m",
                  dim == 2 ? "seam length with damage 1" : "extent along the path of the seam with damage 1");
      sink.result("cracked_area", c->crackedLength() * (dim == 2 ? thick : 1.0), "m^2",
                  "seam area with damage 1 (2D: length x slab thickness)");
      sink.result("crack_tip", c->crackTip(), "m", "farthest fully damaged position along the seam");
      double dmax = 0, snMax = 0, process = 0, pairMax = 0;
      for (int p = 0; p < c->pairs(); ++p) {
        dmax = std::max(dmax, c->state(p).damage);
        pairMax = std::max(pairMax, c->state(p).dissipated / std::max(c->law(p).energy, c->law(p).G2()));
        if (c->state(p).damage > 0 && c->state(p).damage < 1) process += c->tributaryLength(p) * (dim == 2 ? thick : 1.0);
        snMax = std::max(snMax, c->separationNormal(p));
      }
      sink.result("cohesive_max_damage", dmax, "1", "largest damage on the seam");
      sink.result("cohesive_pair_dissipation_max", pairMax, "1",
                  "largest energy dissipated by one pair / its max(G_Ic, G_IIc) (1 = the law's full area)");
      sink.result("process_zone_area", process, "m^2", "seam area with 0 < damage < 1 (2D: length x slab thickness)");
      sink.result("cohesive_max_opening", snMax, "m", "largest normal separation of a seam pair (at the end)");
      sink.result("fracture_energy_of_crack", cohGcArea, "J",
                  "G_c x fully damaged area (2D: length x slab thickness; the dissipation when the process zone is small)");
      sink.note("Cohesive zone on the seam (model.explicit.cohesive, docs/models/cohesive.md): K = " +
                std::to_string(cohLaws.front().stiffness) + " Pa/m, t_c = " + std::to_string(cohLaws.front().strength) +
                " Pa, G_c = " + std::to_string(cohLaws.front().energy) + " J/m^2 (first pair); no node release.");
      if (sleeve) {
        sink.result("sleeve_core_in_bore", sleeveCoreInBore(solver), "1",
                    "of the sleeve pairs the wall passed, the fraction with the core node in the bore and the outer "
                    "node outside the wall (-1: none passed)");
        sink.result("sleeve_radius", sleeveR, "m", "radius of the cylindrical cohesive sleeve");
        sink.note("Sleeve seam (docs/models/cohesive.md \"Sleeve seam\"): cohesive quadrilaterals on a cylinder of "
                  "radius " + std::to_string(sleeveR * 1e3) + " mm around the axis; the wall's edge pushes the core "
                  "side into the bore and the outer side out of the wall (seed 001 section 3.2).");
      } else if (dim == 3 && sc.needle.tip == TipType::Bevel)
        sink.note("3D bevel tip: the cohesive seam plane runs through the needle axis (the lips open around the "
                  "outer section; a hollow needle's core is not cut), docs/models/cohesive.md. EXPERIMENTAL: its "
                  "dissipation is G_c x cracked area, but its needle energy balance can be far off (rim nodes enter "
                  "the wedge with a gap; check needle_energy_balance_error); for a hollow needle use seam: sleeve.");
    } else if (seamOn)
      sink.note("The tissue is pre-cut along the needle path through the tip's leading point (node release when the "
                "tip arrives): the fracture-energy-free limit of the cohesive zone of seeds 001/004.");
    else
      sink.note("No pre-cut seam (an imported mesh, an oblique entry or a rotated bevel): the needle indents the tissue.");
    if (cohOn) reportCrackPath(sink, cpath, *solver.needle(), *solver.cohesive(), meshCopy.X, solver.displacement(),
                               ex.element_size);
    if (ratioMax > 0.1)
      sink.note("Kinetic energy exceeded 10 % of the internal energy: the run was not quasi-static; lower the mass "
                "scaling or the speed.");
    sink.note("Status: " + status);
  };

  Progress progress("explicit FE", options.progress);
  auto t0 = std::chrono::steady_clock::now();
  double nextOut = 0, nextField = 0;
  try {
    record();
    writeFields();
    nextOut = outDt;
    nextField = fieldDt;
    while (solver.time() < T * (1 - 1e-12)) {
      const double t = solver.time(), dt = std::min(solver.timeStep(), T - t);
      auto* n = solver.needle();
      const auto ms = motion.at(t + 0.5 * dt);
      n->pose.tip = entry + motion.at(t).depth * axis;
      n->velocity = ms.velocity;
      // rotation about the axis (profile `rotate`, needle_motion.hpp): 3D spins the surface; a 2D
      // plane-strain model can only show the bevel on one side or the other
      n->pose.bevelSide = bevelSideAt(motion.at(t).axial_angle, e1, e2, dim);
      n->spinRate = dim == 3 ? ms.axial_rate : 0.0;
      n->pose.axis = axis;
      if (n->path) placeOnPath(*n, motion.at(t).depth);
      if (beam) beam->update(*n, solver, n->pose.tip - shape.length * axis, axis, n->pose.bevelSide, thick);
      solver.advanceTo(std::min(T, t + solver.timeStep()));
      if (solver.time() >= nextOut * (1 - 1e-9) || solver.time() >= T * (1 - 1e-12)) {
        record();
        nextOut += outDt;
        progress.update(solver.time() / T);
      }
      if (solver.time() >= nextField * (1 - 1e-9)) {
        writeFields();
        nextField += fieldDt;
      }
    }
  } catch (const SolverError& e) {
    record();
    flush(std::string("stopped: ") + e.what());
    throw;
  }
  progress.finish();
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  sink.result("element_updates_per_second", solver.elementUpdates() / std::max(wall, 1e-9), "1/s",
              "element force evaluations per second of wall time");
  flush("completed");
}

}  // namespace needlesim::engines
