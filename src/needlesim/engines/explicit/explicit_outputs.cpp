// Records and summary results of an explicit run (explicit_run.hpp). Forces, energies and areas of a
// 2D plane-strain model are per metre of thickness times the slab thickness (the needle diameter).
//
// forces.csv: the common columns (results/forces_table.hpp; force_lateral along the frame's lateral,
// tip_* the needle's axis at the tip; a needle on a crack path: force_total along the local tangents,
// force_lateral and force_tip_lateral along the tip's lateral, out-of-plane x the tip's axis), then
//   force_tip [N]          axial force on the tip surface (bevel faces; seed 004's P), > 0 pushing back
//   force_shaft [N]        the rest of force_total: the shaft's friction (force_total = force_tip + force_shaft)
//   moment [N m]           the tissue's moment on the needle about the base centre, about the out-of-plane axis
//   force_tip_lateral [N]  the tissue's force on the tip surface along the frame's lateral (seed 004's Q at bevel 0)
//   axial_torque [N m]     the tissue's torque on the needle about its axis (the base holds minus this)
//   bevel_orientation [rad] the bevel side's angle from lateral towards out-of-plane
//   contact_nodes [1]      tissue nodes in contact with the needle
//   sharp_x, sharp_y, sharp_z [m] the leading point in the tissue frame: a bevel's sharp point (the axis
//                          tip moved by the radius away from the bevel side), a cone's apex
//   (needle_model: beam) tip_slope [rad]: the tip's slope towards lateral; beam_tip_deflection [m]: the
//   beam's tip deflection along lateral under the last step's loads (the applied tip_deflection follows it)
// energy.csv, contact.csv, seam.csv (with a seam): see the column lists below and docs/models/explicit.md.
// markers.csv (model.explicit.markers): as the real-time engines' (engines/realtime/markers.hpp).
#include <algorithm>
#include <cmath>
#include <fmt/format.h>

#include "needlesim/engines/explicit/explicit_run.hpp"
#include "needlesim/engines/explicit/marker_location.hpp"
#include "needlesim/engines/explicit/pain_index.hpp"
#include "needlesim/engines/explicit/path_needle.hpp"
#include "needlesim/engines/explicit/sleeve_setup.hpp"
#include "needlesim/io/field_series.hpp"
#include "needlesim/results/layer_boundaries.hpp"
#include "needlesim/tissue/regions.hpp"

namespace needlesim::explicit_fe {

using Eigen::Vector3d;

namespace {

io::CellType cellType(ElementType t) {
  switch (t) {
    case ElementType::Quad4: return io::CellType::Quad;
    case ElementType::Tri3: return io::CellType::Triangle;
    case ElementType::Hex8: return io::CellType::Hexa;
    case ElementType::Tet4: return io::CellType::Tetra;
  }
  return io::CellType::Quad;
}

std::vector<io::Column> forceColumns(bool beam) {
  std::vector<io::Column> c{{"force_tip", "N"},       {"force_shaft", "N"},           {"moment", "N m"},
                            {"force_tip_lateral", "N"}, {"axial_torque", "N m"},       {"bevel_orientation", "rad"},
                            {"contact_nodes", "1"},     {"sharp_x", "m"},              {"sharp_y", "m"},
                            {"sharp_z", "m"}};
  if (beam) c.insert(c.end(), {{"tip_slope", "rad"}, {"beam_tip_deflection", "m"}});
  return c;
}

const std::vector<io::Column> kEnergyColumns{
    {"time", "s"},          {"depth", "m"},         {"kinetic", "J"},          {"internal", "J"},
    {"strain", "J"},        {"hourglass", "J"},     {"external_work", "J"},    {"contact_work", "J"},
    {"energy_balance", "J"}, {"ke_ie_ratio", "1"},   {"time_step", "s"},        {"needle_work", "J"},
    {"friction_dissipation", "J"}, {"penalty_energy", "J"}, {"needle_energy_balance", "J"}};
const std::vector<io::Column> kContactColumns{{"time", "s"},
                                              {"depth", "m"},
                                              {"contact_area", "m^2"},
                                              {"mean_contact_pressure", "Pa"},
                                              {"max_contact_pressure", "Pa"}};
const std::vector<io::Column> kSeamColumns{{"time", "s"},
                                           {"depth", "m"},
                                           {"open_seam_nodes", "1"},
                                           {"cohesive_stored_energy", "J"},
                                           {"cohesive_dissipation", "J"},
                                           {"cracked_length", "m"},
                                           {"cracked_area", "m^2"}};

// The needle's surface (3D) or outline (2D) for the fields, and its points with `dim` coordinates each.
needle::SurfaceMesh needleSurface(const RigidNeedle& n, int dim) {
  if (n.path) return pathNeedleOutline2D(n);
  return dim == 2 ? needle::needleOutline2D(n.shape, n.pose) : needle::needleSurface3D(n.shape, n.pose, 24, 4);
}
std::vector<double> firstCoordinates(const std::vector<double>& points3, int dim) {
  std::vector<double> pts;
  for (std::size_t i = 0; i < points3.size() / 3; ++i)
    for (int k = 0; k < dim; ++k) pts.push_back(points3[3 * i + k]);
  return pts;
}

}  // namespace

void ExplicitRun::createOutputs() {
  duration_ = motion_.duration();
  depth0_ = motion_.at(0.0).depth;
  forces_ = std::make_unique<results::ForcesTable>(beam_ != nullptr, forceColumns(beam_ != nullptr));
  energy_ = io::Table(kEnergyColumns);
  contact_ = io::Table(kContactColumns);
  if (!seam_.empty()) seam_table_ = io::Table(kSeamColumns);
  contactOut_ = std::make_unique<ContactOutput>(solver_->mesh());  // contact pressure and area (contact_output.hpp)
  fields_ = sink_.fields("tissue", dim_);
  needleFields_ = sink_.fields("needle", dim_);
  if (fields_) {
    std::vector<int> conn(solver_->mesh().conn.begin(), solver_->mesh().conn.end());
    fields_->setMesh(mesh_.X, cellType(mesh_.type), conn);  // the reference points (Warp By Vector deforms them)
    std::vector<int> region = solver_->mesh().region;  // layer, then inclusion (tissue/regions.hpp)
    region.resize(static_cast<std::size_t>(solver_->mesh().elements()), 0);
    fields_->meshCellLabels("region", region, tissue::regionLegend(sc_.tissue));
  }
  if (needleFields_) {
    const auto surface = needleSurface(*solver_->needle(), dim_);
    needleFields_->setMesh(firstCoordinates(surface.points, dim_), dim_ == 2 ? io::CellType::Line : io::CellType::Triangle,
                           surface.cells);
  }
}

// One row of every table at the solver's time. A path needle: depth = arc length of the tip, axial
// force = the reaction along the local tangents, the tip force along the tip's axis.
void ExplicitRun::record() {
  const auto* n = solver_->needle();
  const double thick = thickness_, t = solver_->time();
  const double depth = n->path ? n->station : frame_.axialOf(n->pose.tip - frame_.entry);
  // lateral of the tip's frame (a path needle turns with its path; otherwise the frame's lateral)
  const Vector3d lateral = n->path ? Vector3d(frame_.outOfPlane.cross(n->pose.axis)) : frame_.lateral;
  const Vector3d lead = sc_.needle.tip == TipType::Bevel ? Vector3d(n->pose.tip - shape_.radius * n->pose.bevelSide)
                                                         : n->pose.tip;
  results::NeedleForces f;
  f.time = t;
  f.depth = depth;
  f.velocity = motion_.at(t).velocity;
  f.force_total = (n->path ? -n->driveForce : -frame_.axialOf(n->force)) * thick;
  f.force_lateral = lateral.dot(n->force) * thick;
  f.tip_x = n->pose.tip.x(), f.tip_y = n->pose.tip.y(), f.tip_z = n->pose.tip.z();
  inclusions_.tip(n->pose.tip, n->pose.axis);
  if (beam_) f.tip_deflection = beam_->tipDeflectionAlong(frame_.lateral);
  // torque the tissue applies about the needle axis (the base must hold -torque)
  const double torque = frame_.axialOf(n->moment) * thick;
  const Vector3d& b = n->pose.bevelSide;
  const double tipAxial = -n->tipForce.dot(n->path ? n->pose.axis : frame_.axial) * thick;
  std::vector<double> extra{tipAxial,
                            f.force_total - tipAxial,
                            frame_.outOfPlaneOf(n->moment) * thick,
                            lateral.dot(n->tipForce) * thick,
                            torque,
                            std::atan2(frame_.outOfPlaneOf(b), frame_.lateralOf(b)),
                            static_cast<double>(n->nodesInContact),
                            lead.x(),
                            lead.y(),
                            lead.z()};
  if (beam_) extra.insert(extra.end(), {beam_->tipSlopeAlong(frame_.lateral), beam_->targetDeflectionAlong(frame_.lateral)});
  forces_->add(f, extra);
  peak_ = std::max(peak_, f.force_total);
  if (std::abs(torque) > std::abs(peakTorque_)) peakTorque_ = torque;
  recordEnergies(depth);
  contactOut_->update(*solver_);
  const double area = contactOut_->contactArea() * thick;
  peakArea_ = std::max(peakArea_, area);
  peakPressure_ = std::max(peakPressure_, contactOut_->maxPressure());
  contact_.addRow({t, depth, area, contactOut_->meanPressure(), contactOut_->maxPressure()});
  if (!seam_.empty()) recordSeam(depth);
  recordInclusions(depth);
  markers_.addRow(solver_->time());
  markers_.trackExtremes();
}

void ExplicitRun::recordEnergies(double depth) {
  const auto& E = solver_->energies();
  const double thick = thickness_;
  const double ie = E.internal;
  const double ratio = ie > 0 ? E.kinetic / ie : 0.0;
  energyScale_ = std::max({energyScale_, std::abs(ie), std::abs(E.externalWork), std::abs(E.contactWork), E.kinetic});
  if (solver_->time() > 0.1 * duration_) ratioMax_ = std::max(ratioMax_, ratio);
  balanceMax_ = std::max(balanceMax_, std::abs(E.balance()));
  needleBalanceMax_ = std::max(needleBalanceMax_, std::abs(E.balanceWithNeedle()));
  needleWorkMax_ = std::max(needleWorkMax_, std::abs(E.needleWork));
  energy_.addRow({solver_->time(), depth, E.kinetic * thick, ie * thick, E.strain * thick, E.hourglass * thick,
                  E.externalWork * thick, E.contactWork * thick, E.balance() * thick, ratio, solver_->timeStep(),
                  E.needleWork * thick, E.frictionDissipation * thick, E.penaltyEnergy * thick,
                  E.balanceWithNeedle() * thick});
}

void ExplicitRun::recordSeam(double depth) {
  const auto& E = solver_->energies();
  const double thick = thickness_;
  const auto* c = solver_->cohesive();
  const double open = c ? c->fullyDamaged() : static_cast<int>(seam_.size()) - solver_->activeTies();
  seam_table_.addRow({solver_->time(), depth, open, E.cohesiveStored * thick, E.cohesiveDissipated * thick,
                      c ? crackedLength() : 0.0, c ? c->crackedLength() * (dim_ == 2 ? thick : 1.0) : 0.0});
  if (!c) return;
  cohGcArea_ = 0.0;
  for (int p = 0; p < c->pairs(); ++p)
    if (c->state(p).damage >= 1.0 - 1e-12) cohGcArea_ += cohGc_[c->node(p, 0)] * c->tributaryLength(p) * thick;
}

// Mean displacement of the nodes of each inclusion's elements (results/inclusion_motion.hpp).
// Markers: x = depth from the entry face, y = lateral from the path line through the entry point, z =
// from the insertion plane (2D: none); each the material point at that reference position.
void ExplicitRun::placeMarkers() {
  for (const auto& spec : ex_.markers) {
    const Vector3d X = frame_.entry + Vector3d(spec.x, spec.y, dim_ == 3 ? spec.z : 0.0);
    auto m = locateMarker(solver_->mesh(), X);
    if (!m) throw SolverError(fmt::format("explicit: marker {} lies outside the tissue mesh", spec.name));
    m->name = spec.name;
    markers_.add(std::move(*m));
  }
}

void ExplicitRun::recordInclusions(double depth) {
  if (inclusions_.empty()) return;
  const auto& u = solver_->displacement();
  std::vector<Vector3d> mean;
  for (const auto& nodes : inclusionNodes_) {
    Vector3d s = Vector3d::Zero();
    for (int n : nodes)
      for (int i = 0; i < dim_; ++i) s[i] += u[static_cast<std::size_t>(n) * dim_ + i];
    mean.push_back(s / static_cast<double>(nodes.size()));
  }
  inclusions_.add(solver_->time(), depth, mean);
}

void ExplicitRun::writeFields() {
  if (fields_) {
    const auto& u = solver_->displacement();
    std::vector<double> sig, vm, ls, J;
    solver_->cellFields(sig, vm, ls, J);
    fields_->beginStep(solver_->time());
    fields_->pointData("displacement", u, dim_, "m");
    fields_->pointData("velocity", solver_->velocity(), dim_, "m/s");
    contactOut_->update(*solver_);
    fields_->pointData("contact_pressure", contactOut_->pressure(), 1, "Pa");
    fields_->cellData("cauchy_stress", sig, 6, "Pa");
    fields_->cellData("von_mises", vm, 1, "Pa");
    fields_->cellData("log_strain", ls, 6, "1");
    fields_->cellData("J", J, 1, "1");
    fields_->endStep();
  }
  if (!needleFields_) return;
  needleFields_->beginStep(solver_->time());
  needleFields_->stepPoints(firstCoordinates(needleSurface(*solver_->needle(), dim_).points, dim_));
  needleFields_->endStep();
}

// Cracked length: 2D the fully damaged seam length; 3D its extent along the path (the area is reported apart).
double ExplicitRun::crackedLength() const {
  const auto* c = solver_->cohesive();
  if (dim_ == 2) return c->crackedLength();
  double lo = 1e300, hi = -1e300;
  for (int p = 0; p < c->pairs(); ++p)
    if (c->state(p).damage >= 1.0) lo = std::min(lo, c->position(p)), hi = std::max(hi, c->position(p));
  return hi >= lo ? hi - lo : 0.0;
}

void ExplicitRun::finish(const std::string& status) {
  const io::Table& ft = forces_->table();
  const auto depth = ft.column("depth"), force = ft.column("force_total"), time = ft.column("time");
  std::vector<double> dmm;
  for (double d : depth) dmm.push_back((d - depth0_) * 1e3);
  io::Plot fp{"Needle force against needle displacement", "needle displacement [mm]", "force [N]", {}};
  fp.series.push_back({"axial force (reaction at the base)", dmm, force});
  fp.series.push_back({"tip surface", dmm, ft.column("force_tip"), false, true});
  results::markLayerBoundaries(fp, sc_, depth0_);
  sink_.plot(fp);
  io::Plot ep{"Energies", "time [s]", "energy [J]", {}};
  for (const char* c : {"kinetic", "internal", "external_work", "contact_work", "energy_balance"})
    ep.series.push_back({c, time, energy_.column(c)});
  if (cohesive_) ep.series.push_back({"cohesive_dissipation", seam_table_.column("time"), seam_table_.column("cohesive_dissipation")});
  sink_.plot(ep);
  reportForces();
  if (status == "completed") warnZeroForce(sc_, peak_, sink_);
  reportEnergies();
  if (cohesive_) reportCohesive();
  reportNotes(status);
  inclusions_.report(sink_);
  markers_.reportResults(sink_);
  markers_.plot(sink_);
  markers_.writeTable(sink_);
  sink_.table("forces", forces_->release());
  sink_.table("energy", energy_);
  sink_.table("contact", contact_);
  if (!seam_.empty()) sink_.table("seam", seam_table_);
}

void ExplicitRun::reportForces() {
  const io::Table& ft = forces_->table();
  const auto force = ft.column("force_total"), tipAx = ft.column("force_tip");
  const auto* n = solver_->needle();
  const double thick = thickness_;
  sink_.result("peak_force", peak_, "N", "largest axial needle force (reaction at the base)");
  sink_.result("final_force", force.empty() ? 0.0 : force.back(), "N", "axial needle force at the end");
  sink_.result("peak_contact_area", peakArea_, "m^2",
               "largest needle-tissue contact area (nodal tributary areas; 2D: times the slab thickness)");
  sink_.result("max_contact_pressure", peakPressure_, "Pa", "largest nodal needle-tissue contact pressure");
  sink_.result("peak_axial_torque", peakTorque_, "N m", "largest tissue torque about the needle axis (rotation)");
  // Needle forces split as seed 004 Fig 8: P, Q on the tip (bevel) faces, q_x, q_y on the wall,
  // F_x = P + q_x, F_y = Q + q_y (axial, lateral towards the bevel side); seed 001's pain index.
  if (!tipAx.empty()) {
    const double Q = n->tipForce.dot(n->pose.bevelSide) * thick, Fy = n->force.dot(n->pose.bevelSide) * thick;
    sink_.result("tip_force_axial", tipAx.back(), "N", "P: axial force on the tip (bevel) faces at the end; F_x = P + q_x (seed 004)");
    sink_.result("tip_force_lateral", Q, "N",
                 "Q: lateral force on the tip (bevel) faces at the end, + towards the bevel side; F_y = Q + q_y (seed 004)");
    sink_.result("peak_tip_force_axial", *std::max_element(tipAx.begin(), tipAx.end()), "N",
                 "largest axial force on the tip faces");
    sink_.result("wall_force_axial", force.back() - tipAx.back(), "N", "q_x: axial force on the needle wall at the end");
    sink_.result("wall_force_lateral", Fy - Q, "N", "q_y: lateral force on the needle wall at the end, + towards the bevel side");
  }
  if (dim_ == 3) {
    const auto pdi = painIndex(ft.column("time"), force,
                               needleAnnulusArea(sc_.needle.outer_diameter, sc_.needle.inner_diameter),
                               painBasicStress(sc_.tissue.layers.front().material));
    sink_.result("pain_index_peak", pdi.peak, "1",
                 "PDI = F / (pi (R^2 - r^2)) / sigma*(0.3 strain) of the entry layer, peak (seed 001 eqs 7-8)");
    sink_.result("pain_index_mean", pdi.mean, "1", "PDI averaged over the insertion time (seed 001 eqs 7-8)");
    sink_.result("pain_basic_stress", pdi.basicStress, "Pa", "sigma*: entry layer's stress at 0.3 compressive strain");
  }
  if (!beam_) return;
  sink_.result("final_tip_deflection", beam_->tipDeflectionAlong(frame_.lateral), "m",
               "tip deflection of the deformable needle at the end along the frame's lateral (tip_deflection)");
  sink_.result("final_tip_slope", beam_->tipSlopeAlong(frame_.lateral), "rad",
               "tip slope of the deformable needle at the end, towards the frame's lateral");
  sink_.result("needle_coupling_residual_mean", beam_->meanResidual(), "m",
               "mean |beam tip deflection under the last step's loads - applied (followed) deflection| in contact");
  sink_.note("Deformable needle (needle_model: beam): Euler-Bernoulli cantilever clamped at the base, EI = " +
             std::to_string(beam_->EI()) + " N m^2, loaded by the contact resultant each step; the contact "
             "surface is a straight needle along the deflected tip axis (docs/models/explicit.md).");
}

void ExplicitRun::reportEnergies() {
  const auto& E = solver_->energies();
  const double thick = thickness_;
  sink_.result("kinetic_internal_ratio_max", ratioMax_, "1",
               "largest kinetic / internal energy after the first 10 % (quasi-static if < 0.05-0.1)");
  sink_.result("energy_balance_error", balanceMax_ / energyScale_, "1", "largest |energy balance| / largest energy term");
  sink_.result("needle_work", E.needleWork * thick, "J", "work done by the moving needle (its reaction x its travel)");
  sink_.result("friction_dissipation", E.frictionDissipation * thick, "J", "Coulomb friction force x slip on the needle");
  sink_.result("penalty_energy", E.penaltyEnergy * thick, "J", "energy stored in the needle contact penalty at the end");
  sink_.result("viscous_dissipation", (E.internal - E.strain - E.hourglass) * thick, "J",
               "internal work less strain and hourglass energy (bulk viscosity, viscoelasticity)");
  sink_.result("needle_energy_balance_error", needleBalanceMax_ / needleWorkMax_, "1",
               "largest |needle work - kinetic - internal - cohesive - friction - penalty| / largest needle work");
  sink_.result("elements", solver_->mesh().elements(), "1", "elements");
  sink_.result("steps", static_cast<double>(solver_->steps()), "1", "time steps");
  sink_.result("time_step", solver_->timeStep(), "s", "last stable time step (after mass scaling)");
  sink_.result("added_mass", solver_->totalMass() / solver_->physicalMass() - 1.0, "1",
               "mass added by mass scaling / physical mass");
  warnOnEnergyBalance(balanceMax_ / energyScale_);
  warnOnNeedleBalance(needleBalanceMax_ / needleWorkMax_);
}

// The needle's work against what the tissue stored and dissipated: the shipped block examples
// stay within 0.15; far beyond, contact did work on the tissue that the needle's reaction does
// not show (a node caught deep inside the needle), and force and displacements are not to be trusted.
void ExplicitRun::warnOnNeedleBalance(double needle) {
  constexpr double kLimit = 0.5;
  if (std::isfinite(needle) && needle > kLimit)
    sink_.warning(fmt::format("The needle's work balances what the tissue took up only within {:.3g} times that work "
                              "(needle_energy_balance_error; energy.csv contact_work against needle_work): contact "
                              "forces did work the needle's reaction does not show, so forces and displacements are "
                              "not to be trusted. Refine the mesh along the needle path or lower the speed.",
                              needle));
}

// A tissue energy balance far from zero (round-off, 1e-14, when the step is
// stable) means the results do not conserve energy.
void ExplicitRun::warnOnEnergyBalance(double body) {
  if (std::isfinite(body) && body > 0.01)
    sink_.warning(fmt::format("The energy balance of the tissue is off by {:.3g} % of its largest energy term "
                              "(energy_balance_error; energy.csv): check the time step and the contact settings.",
                              100.0 * body));
}

void ExplicitRun::reportCohesive() {
  const auto* c = solver_->cohesive();
  const auto& E = solver_->energies();
  const double thick = thickness_, areaScale = dim_ == 2 ? thick : 1.0;
  sink_.result("cohesive_dissipation", E.cohesiveDissipated * thick, "J",
               "energy dissipated by the cohesive zone (slab as thick as the needle in 2D)");
  sink_.result("cohesive_stored", E.cohesiveStored * thick, "J", "elastic energy stored in the cohesive zone");
  sink_.result("cracked_length", crackedLength(), "m",
               dim_ == 2 ? "seam length with damage 1" : "extent along the path of the seam with damage 1");
  sink_.result("cracked_area", c->crackedLength() * areaScale, "m^2", "seam area with damage 1 (2D: length x slab thickness)");
  // no fully damaged pair: no crack tip to report (crackTip() is -inf)
  if (const double tip = c->crackTip(); std::isfinite(tip))
    sink_.result("crack_tip", tip, "m", "farthest fully damaged position along the seam");
  double dmax = 0, snMax = 0, process = 0, pairMax = 0;
  for (int p = 0; p < c->pairs(); ++p) {
    dmax = std::max(dmax, c->state(p).damage);
    pairMax = std::max(pairMax, c->state(p).dissipated / std::max(c->law(p).energy, c->law(p).G2()));
    if (c->state(p).damage > 0 && c->state(p).damage < 1) process += c->tributaryLength(p) * areaScale;
    snMax = std::max(snMax, c->separationNormal(p));
  }
  sink_.result("cohesive_max_damage", dmax, "1", "largest damage on the seam");
  sink_.result("cohesive_pair_dissipation_max", pairMax, "1",
               "largest energy dissipated by one pair / its max(G_Ic, G_IIc) (1 = the law's full area)");
  sink_.result("process_zone_area", process, "m^2", "seam area with 0 < damage < 1 (2D: length x slab thickness)");
  sink_.result("cohesive_max_opening", snMax, "m", "largest normal separation of a seam pair (at the end)");
  sink_.result("fracture_energy_of_crack", cohGcArea_, "J",
               "G_c x fully damaged area (2D: length x slab thickness; the dissipation when the process zone is small)");
  sink_.note(fmt::format("Cohesive zone on the seam (model.explicit.cohesive, docs/models/cohesive.md): K = {} Pa/m, "
                         "t_c = {} Pa, G_c = {} J/m^2 (first pair); no node release.",
                         cohLaws_.front().stiffness, cohLaws_.front().strength, cohLaws_.front().energy));
  if (sleeve_) {
    sink_.result("sleeve_core_in_bore", sleeveCoreInBore(*solver_), "1",
                 "of the sleeve pairs the wall passed, the fraction with the core node in the bore and the outer "
                 "node outside the wall (-1: none passed)");
    sink_.result("sleeve_radius", sleeveRadius_, "m", "radius of the cylindrical cohesive sleeve");
  }
  reportCrackPath(sink_, crackPath_, *solver_->needle(), *c, mesh_.X, solver_->displacement(), ex_.element_size);
}

void ExplicitRun::reportNotes(const std::string& status) {
  if (dim_ == 2)
    sink_.note("2D plane strain: forces and energies are per metre of thickness times the needle diameter (" +
               std::to_string(thickness_ * 1e3) + " mm), i.e. a slab as thick as the needle.");
  if (sleeve_)
    sink_.note("Sleeve seam (docs/models/cohesive.md \"Sleeve seam\"): cohesive quadrilaterals on a cylinder of "
               "radius " + std::to_string(sleeveRadius_ * 1e3) + " mm around the axis; the wall's edge pushes the core "
               "side into the bore and the outer side out of the wall (seed 001 section 3.2).");
  else if (cohesive_ && dim_ == 3 && sc_.needle.tip == TipType::Bevel)
    sink_.note("3D bevel tip: the cohesive seam plane runs through the needle axis (the lips open around the "
               "outer section; a hollow needle's core is not cut), docs/models/cohesive.md. EXPERIMENTAL: its "
               "dissipation is G_c x cracked area, but its needle energy balance can be far off (rim nodes enter "
               "the wedge with a gap; check needle_energy_balance_error); for a hollow needle use seam: sleeve.");
  else if (!cohesive_ && seamOn_)
    sink_.note("The tissue is pre-cut along the needle path through the tip's leading point (node release when the "
               "tip arrives): the fracture-energy-free limit of the cohesive zone of seeds 001/004.");
  else if (!cohesive_)
    sink_.note("No pre-cut seam (an imported mesh, an oblique entry or a rotated bevel): the needle indents the tissue.");
  if (ratioMax_ > 0.1)
    sink_.warning("Kinetic energy exceeded 10 % of the internal energy: the run was not quasi-static; lower the mass "
               "scaling or the speed.");
  sink_.note("Status: " + status);
}

}  // namespace needlesim::explicit_fe
