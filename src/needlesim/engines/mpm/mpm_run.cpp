// The mpm run: the solver steps under the prescribed needle motion; rows of
// forces.csv (results/forces_table.hpp, the shared insertion frame), energy,
// markers, fracture, inclusion motion and particle fields. docs/models/mpm.md.
#include "needlesim/engines/mpm/mpm_run.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cstdint>
#include <limits>
#include <optional>

#include "needlesim/core/error.hpp"
#include "needlesim/core/progress.hpp"
#include "needlesim/engines/mpm/cuda/device_select.hpp"
#include "needlesim/results/checkpoint.hpp"

namespace needlesim::engines {

using mpm::MpmSolver;
using mpm::Vec3;

namespace {

// The solver's materials, points and needle (rigid body 0); returns the points of each inclusion.
std::vector<std::vector<std::size_t>> populate(MpmSolver& solver, const Scenario& sc, const MpmSetup& setup) {
  for (const auto& m : setup.materials) solver.addMaterial(m);
  auto members = addTissue(solver, sc, setup);
  solver.addRigid(setup.needle);
  solver.finalize();
  attachRequestedDevice(solver, sc);  // model.mpm.device: cuda (cuda/device_select.hpp)
  return members;
}

std::vector<io::Column> engineForceColumns() {
  return {{"force_tip", "N"},   {"force_shaft", "N"}, {"contact_nodes", "1"}, {"time_step", "s"},
          {"sharp_x", "m"},     {"sharp_y", "m"},     {"sharp_z", "m"},       {"force_tip_lateral", "N"}};
}

// energy.csv; with a sliding inclusion also the energy stored in the two bodies' pair contact.
std::vector<io::Column> energyColumns(int bodies) {
  std::vector<io::Column> c{{"time", "s"}, {"depth", "m"}, {"kinetic", "J"}, {"internal", "J"}, {"ke_ie_ratio", "1"}};
  if (bodies > 1) c.push_back({"contact", "J"});
  return c;
}

Vec3 meanPosition(const MpmSolver& s, const std::vector<std::size_t>& points) {
  Vec3 sum = Vec3::Zero();
  for (const std::size_t p : points) sum += s.position(p);
  return sum / static_cast<double>(points.size());
}

// A table of the checkpoint that must have the columns of `like` (else it belongs to another set-up).
io::Table tableLike(io::BinaryReader& r, const io::Table& like) {
  io::Table u = r.table();
  bool same = u.columns().size() == like.columns().size();
  for (std::size_t c = 0; same && c < u.columns().size(); ++c) same = u.columns()[c].name == like.columns()[c].name;
  if (!same) r.fail("holds tables with other columns (another set-up)");
  return u;
}

// The rows of a saved forces table added again (the common columns, then the engine's).
void replayForces(const io::Table& saved, results::ForcesTable& into) {
  for (std::size_t i = 0; i < saved.rows(); ++i) {
    const auto v = [&](std::size_t c) { return saved.at(i, c); };
    const results::NeedleForces f{v(0), v(1), v(2), v(3), v(4), v(5), v(6), v(7)};
    std::vector<double> extra;
    for (std::size_t c = 8; c < saved.columns().size(); ++c) extra.push_back(v(c));
    into.add(f, extra);
  }
}

// The rows of a saved inclusions table added again (per inclusion ux, uy, uz and three derived columns).
void replayInclusions(const io::Table& saved, std::size_t count, results::InclusionMotion& into) {
  for (std::size_t i = 0; i < saved.rows(); ++i) {
    std::vector<Eigen::Vector3d> u;
    for (std::size_t k = 0; k < count; ++k)
      u.emplace_back(saved.at(i, 2 + 6 * k), saved.at(i, 3 + 6 * k), saved.at(i, 4 + 6 * k));
    into.add(saved.at(i, 0), saved.at(i, 1), u);
  }
}

}  // namespace

MpmRun::MpmRun(const Scenario& sc, ResultSink& sink, const RunOptions& options)
    : sc_(sc),
      spec_(sc.model.mpm),
      sink_(sink),
      options_(options),
      setup_(mpmSetup(sc)),
      solver_(setup_.config),
      inclusionPoints_(populate(solver_, sc, setup_)),
      setupSeconds_(std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0_).count()),
      motion_(sc.insertion),
      duration_(motion_.duration()),
      forces_(false, engineForceColumns()),
      energy_(energyColumns(setup_.config.bodies)),
      markers_(spec_.markers, solver_, setup_.entry),
      fields_(spec_.field_interval > 0.0 ? sink.fields("particles", 3) : nullptr, solver_, setup_.shift,
              sc.tissue),
      needleFields_(spec_.field_interval > 0.0 ? sink.fields("needle", 3) : nullptr, solver_.rigid(kNeedle),
                    setup_.shift),
      inclusions_(sc.tissue.inclusions, setup_.frame) {
  for (const auto& pts : inclusionPoints_) inclusionStart_.push_back(meanPosition(solver_, pts));
  fracture_.init(solver_, setup_.entry, setup_.frame.axial);
  sum_.dtMin = std::numeric_limits<double>::infinity();
  placeAt(0.0);
  next_.nextOut = sc.output.interval;
  next_.nextField = spec_.field_interval;
  if (spec_.marker_depth_step > 0)
    next_.nextMarkerDepth = (std::floor(ms_.depth / spec_.marker_depth_step) + 1) * spec_.marker_depth_step;
}

// The needle at time t: depth and bevel turn of the motion profile (the
// profile's axial angle includes insertion.bevel_orientation).
void MpmRun::placeAt(double t) {
  ms_ = motion_.at(t);
  placeNeedle(solver_.rigid(kNeedle), setup_, ms_.depth, bevelSideAt(ms_), ms_.velocity);
}

MpmRun::Vec3 MpmRun::bevelSideAt(const MotionState& m) const {
  return setup_.frame.bevelSide(m.axial_angle - setup_.frame.bevelOrientation);
}

// The particles and the needle where the motion puts it at the recorded depth (the solver
// places it at the start of each step).
void MpmRun::writeFields(double t) {
  solver_.syncFromDevice();  // GPU: the particles at output times only
  fields_.write(solver_, t);
  mpm::RigidBody shown = solver_.rigid(kNeedle);
  placeNeedle(shown, setup_, ms_.depth, bevelSideAt(ms_), ms_.velocity);
  needleFields_.write(shown, t);
}

bool MpmRun::finished(double t) const { return !(t < duration_ - 1e-12 * std::max(1.0, duration_)); }

void MpmRun::startFresh() {
  results::NeedleForces f;
  f.depth = ms_.depth;
  f.velocity = ms_.velocity;
  const Vec3 tip = setup_.frame.onAxis(ms_.depth), sharp = needleTip(setup_, ms_.depth, solver_.rigid(kNeedle).bevelSide);
  f.tip_x = tip.x();
  f.tip_y = tip.y();
  f.tip_z = tip.z();
  forces_.add(f, {0.0, 0.0, 0.0, 0.0, sharp.x(), sharp.y(), sharp.z(), 0.0});
  std::vector<double> zero(energy_.columns().size(), 0.0);
  zero[1] = ms_.depth;
  energy_.addRow(zero);
  markers_.record(solver_, 0.0, ms_.depth);
  recordInclusions(0.0);
  writeFields(0.0);
}

void MpmRun::recordInclusions(double t) {
  if (inclusions_.empty()) return;
  std::vector<Eigen::Vector3d> u;
  for (std::size_t i = 0; i < inclusionPoints_.size(); ++i)
    u.push_back(meanPosition(solver_, inclusionPoints_[i]) - inclusionStart_[i]);
  inclusions_.add(t, ms_.depth, u);
}

// One output row from the impulses since the last one (forces.csv in the
// shared frame: force_total resists insertion, force_lateral along the
// frame's lateral direction, the tip in the tissue frame).
void MpmRun::recordRow(double t, const mpm::StepReport& rep) {
  solver_.syncFromDevice();  // GPU: fracture, markers and inclusions read the particles
  const Vec3 F = imp_.total / imp_.time, Ftip = imp_.tip / imp_.time, Fsh = imp_.shaft / imp_.time;
  const Vec3& axial = setup_.frame.axial;
  sum_.lastForce = 0.0 - F.dot(axial);  // 0 - x: no -0 in the table
  sum_.lastTip = 0.0 - Ftip.dot(axial);
  sum_.lastShaft = 0.0 - Fsh.dot(axial);
  if (sum_.lastForce > sum_.peak) {
    sum_.peak = sum_.lastForce;
    sum_.peakDepth = ms_.depth;
  }
  // tip_*: the needle's axis at the tip; sharp_*: the leading point (a bevel's sharp point)
  const Vec3 tip = setup_.frame.onAxis(ms_.depth), sharp = needleTip(setup_, ms_.depth, solver_.rigid(kNeedle).bevelSide);
  const results::NeedleForces f{t,         ms_.depth, ms_.velocity, sum_.lastForce, setup_.frame.lateralOf(F),
                                tip.x(),   tip.y(),   tip.z()};
  forces_.add(f, {sum_.lastTip, sum_.lastShaft, static_cast<double>(imp_.contactNodes), rep.dt, sharp.x(), sharp.y(),
                  sharp.z(), setup_.frame.lateralOf(Ftip)});
  std::vector<double> e{t, ms_.depth, rep.kinetic, rep.internal, rep.internal > 0 ? rep.kinetic / rep.internal : 0.0};
  if (setup_.config.bodies > 1) e.push_back(rep.contact);
  energy_.addRow(e);
  imp_ = Impulses{};
  fracture_.check(solver_, t, ms_.depth);
  if (spec_.marker_depth_step <= 0.0) markers_.record(solver_, t, ms_.depth);
  recordInclusions(t);
}

void MpmRun::step() {
  placeAt(solver_.time());
  const mpm::StepReport rep = solver_.step();
  ++sum_.steps;
  sum_.dtMin = std::min(sum_.dtMin, rep.dt);
  sum_.dtMax = std::max(sum_.dtMax, rep.dt);
  const mpm::RigidForce& f = solver_.rigidForce(kNeedle);
  imp_.total += rep.dt * f.total;
  imp_.tip += rep.dt * f.tip;
  imp_.shaft += rep.dt * f.shaft;
  imp_.time += rep.dt;
  imp_.contactNodes = std::max(imp_.contactNodes, f.contactNodes);
  const double t = solver_.time();
  ms_ = motion_.at(std::min(t, duration_));
  const bool last = finished(t);
  const double outEvery = sc_.output.interval;
  if (outEvery <= 0.0 || t >= next_.nextOut - 1e-12 || last) {
    while (outEvery > 0.0 && next_.nextOut <= t + 1e-12) next_.nextOut += outEvery;
    recordRow(t, rep);
  }
  if (spec_.marker_depth_step > 0.0 && ms_.depth >= next_.nextMarkerDepth - 1e-12) {
    solver_.syncFromDevice();
    markers_.record(solver_, t, ms_.depth);
    while (next_.nextMarkerDepth <= ms_.depth + 1e-12) next_.nextMarkerDepth += spec_.marker_depth_step;
  }
  if (fields_.series() && (t >= next_.nextField - 1e-12 || last)) {
    writeFields(t);
    while (next_.nextField <= t + 1e-12) next_.nextField += spec_.field_interval;
  }
}

// Checkpoints (results/checkpoint.hpp, docs/models/mpm.md "Checkpoints"): the
// engine's state between two steps (the tables so far, the accumulators of
// the next output row, the next output times, the markers' and the fracture
// tracker's records) followed by the solver's. Everything else is set up
// again from the scenario exactly as in the first run.
namespace {
constexpr std::uint32_t kEngineLayout = 2;
io::Checkpoint::Series seriesOf(const mpm_outputs::ParticleFields& fields, const mpm_outputs::NeedleFields& needle) {
  io::Checkpoint::Series series;
  if (fields.series()) series.emplace_back("particles", fields.series());
  if (needle.series()) series.emplace_back("needle", needle.series());
  return series;
}
}  // namespace

void MpmRun::saveCheckpoint() {
  solver_.syncFromDevice();
  io::BinaryWriter w;
  w.tag("mpm_engine");
  w.pod(kEngineLayout);
  const io::Table* tables[] = {&forces_.table(), &energy_, &markers_.table(), &fracture_.table, &inclusions_.table()};
  for (const io::Table* t : tables) w.table(*t);
  for (const Vec3* v : {&imp_.total, &imp_.tip, &imp_.shaft})
    for (int d = 0; d < 3; ++d) w.pod((*v)[d]);
  for (const double x : {imp_.time, sum_.peak, sum_.peakDepth, sum_.lastForce, sum_.lastTip, sum_.lastShaft,
                         sum_.dtMin, sum_.dtMax, next_.nextOut, next_.nextField, next_.nextMarkerDepth})
    w.pod(x);
  w.pod(static_cast<std::int32_t>(imp_.contactNodes));
  w.pod(sum_.steps);
  w.vec(markers_.largest());
  w.vec(fracture_.separated);
  w.pod(static_cast<std::uint64_t>(fracture_.total));
  for (const double x : {fracture_.onsetDepth, fracture_.onsetTime, fracture_.deepest, fracture_.widest}) w.pod(x);
  solver_.saveState(w);
  options_.checkpoint->write("mpm", w, seriesOf(fields_, needleFields_), solver_.time(), sum_.steps);
}

void MpmRun::loadCheckpoint() {
  io::BinaryReader r = options_.checkpoint->load("mpm", seriesOf(fields_, needleFields_));
  r.tag("mpm_engine");
  if (r.pod<std::uint32_t>() != kEngineLayout) r.fail("holds an mpm engine state of another layout (another version)");
  const io::Table forces = tableLike(r, forces_.table());
  forces_ = results::ForcesTable(false, engineForceColumns());
  replayForces(forces, forces_);
  energy_ = tableLike(r, energy_);
  markers_.table() = tableLike(r, markers_.table());
  fracture_.table = tableLike(r, fracture_.table);
  const io::Table inclusions = tableLike(r, inclusions_.table());
  inclusions_ = results::InclusionMotion(sc_.tissue.inclusions, setup_.frame);
  replayInclusions(inclusions, sc_.tissue.inclusions.size(), inclusions_);
  for (Vec3* v : {&imp_.total, &imp_.tip, &imp_.shaft})
    for (int d = 0; d < 3; ++d) r.pod((*v)[d]);
  for (double* x : {&imp_.time, &sum_.peak, &sum_.peakDepth, &sum_.lastForce, &sum_.lastTip, &sum_.lastShaft,
                    &sum_.dtMin, &sum_.dtMax, &next_.nextOut, &next_.nextField, &next_.nextMarkerDepth})
    r.pod(*x);
  imp_.contactNodes = r.pod<std::int32_t>();
  r.pod(sum_.steps);
  markers_.setLargest(r.vec<double>(markers_.names().size(), "markers"));
  fracture_.separated = r.vec<std::uint8_t>(fracture_.a.size(), "fracture pairs");
  fracture_.total = static_cast<std::size_t>(r.pod<std::uint64_t>());
  for (double* x : {&fracture_.onsetDepth, &fracture_.onsetTime, &fracture_.deepest, &fracture_.widest}) r.pod(*x);
  solver_.loadState(r);
  ms_ = motion_.at(std::min(solver_.time(), duration_));
  const io::Checkpoint& ck = *options_.checkpoint;
  resumedNote_ = fmt::format(
      "Resumed from the checkpoint at t = {:.9g} s (step {}, depth {:.4g} mm); steps before it ran in an earlier "
      "process.",
      ck.resumedTime(), ck.resumedSteps(), ms_.depth * 1e3);
}

void MpmRun::run() {
  io::Checkpoint* ck = options_.checkpoint;
  if (ck && ck->resuming()) loadCheckpoint();
  else startFresh();
  steps0_ = sum_.steps;
  Progress progress("mpm", options_.progress);
  const auto run0 = std::chrono::steady_clock::now();
  try {
    while (!finished(solver_.time())) {
      step();
      const bool last = finished(solver_.time());
      // A stop request (Ctrl-C, SIGTERM) gets a final checkpoint, so --resume goes on from this step.
      const bool stop = !last && stopRequested();
      if (ck && !last && (stop || ck->due(sum_.steps))) saveCheckpoint();
      if (stop) {
        progress.finish();
        throwIfStopRequested(fmt::format("mpm at step {}, t = {:.6g} s", sum_.steps, solver_.time()));
      }
      if ((sum_.steps & 31) == 0)
        progress.update(solver_.time() / duration_,
                        fmt::format("depth {:.2f} mm, F {:.3g} N", ms_.depth * 1e3, sum_.lastForce));
      if (options_.stopAfterSteps > 0 && sum_.steps >= options_.stopAfterSteps && !last) {
        progress.finish();
        throw RunInterrupted(
            fmt::format("mpm: stopped after {} steps (test hook RunOptions::stopAfterSteps)", sum_.steps));
      }
    }
  } catch (const SolverError&) {
    progress.finish();
    sink_.warning("The run stopped early (see the error); the results cover the time up to the failure.");
    if (!resumedNote_.empty()) sink_.note(resumedNote_);
    emit(true);
    throw;
  }
  progress.finish();
  runNotes(std::chrono::duration<double>(std::chrono::steady_clock::now() - run0).count());
  if (!resumedNote_.empty()) sink_.note(resumedNote_);
  emit(false);
}

void runMpm(const Scenario& sc, ResultSink& sink, const RunOptions& options) {
  guardAndAnnounce(sc, mpmStepPlan(sc), sink, options);
  std::optional<MpmRun> run;
  {
    // filling millions of points has no step loop to see a stop: a stop here ends run and sweep at once
    const BlockingCall setUp("mpm: setting up the material points and the grid");
    run.emplace(sc, sink, options);
  }
  run->run();
}

}  // namespace needlesim::engines
