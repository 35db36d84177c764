#include "needlesim/engines/realtime3d/realtime3d_engine.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>

#include "needlesim/core/error.hpp"
#include "needlesim/core/progress.hpp"
#include "needlesim/engines/realtime/linear_range.hpp"
#include "needlesim/engines/realtime/markers.hpp"
#include "needlesim/engines/realtime/run_report.hpp"
#include "needlesim/engines/realtime/scenario_config.hpp"
#include "needlesim/engines/run_cost.hpp"
#include "needlesim/insertion/motion_profile.hpp"
#include "needlesim/io/field_series.hpp"
#include "needlesim/results/forces_table.hpp"
#include "needlesim/results/inclusion_motion.hpp"
#include "needlesim/tissue/regions.hpp"

namespace needlesim::engines {

using namespace realtime3d;

namespace {

std::vector<io::Column> engineColumns() {
  return {{"force_stiffness", "N"},  {"force_cutting", "N"},      {"force_friction", "N"},
          {"force_x", "N"},          {"force_y", "N"},            {"force_z", "N"},
          {"force_out_of_plane", "N"}, {"tip_deflection_z", "m"}, {"tip_load_y", "N"},
          {"tip_load_z", "N"},       {"phase", "1"},              {"coupled_nodes", "1"},
          {"sticking_nodes", "1"}};
}

constexpr int kShapePoints = 41;

// The fields of one run: the tissue (tets on their reference points, region, displacement, von Mises)
// and the needle centre line, in the centred tissue frame.
class Fields3d {
 public:
  Fields3d(ResultSink& sink, const Session& s, const TissueSpec& spec) : s_(s) {
    tissue_ = sink.fields("tissue", 3);
    needle_ = sink.fields("needle", 3);
    const auto& m = s.mesh();
    reference_ = m.X;
    for (std::size_t i = 0; i < reference_.size(); ++i) reference_[i] -= s.cornerShift()[static_cast<Eigen::Index>(i % 3)];
    if (tissue_) {  // the reference points (Warp By Vector deforms them) and the region of every tet
      tissue_->setMesh(reference_, io::CellType::Tetra, m.conn);
      tissue_->meshCellLabels("region", tissue::cellRegions(spec, reference_, 3, m.conn, 4), tissue::regionLegend(spec));
    }
    std::vector<int> conn;
    for (int k = 0; k + 1 < kShapePoints; ++k) { conn.push_back(k); conn.push_back(k + 1); }
    s.needleShape(kShapePoints, line_);
    if (needle_) needle_->setMesh(std::vector<double>(line_.data(), line_.data() + line_.size()), io::CellType::Line, conn);
  }
  void write(double t) {
    if (tissue_) {
      const auto& u = s_.displacement();
      std::vector<double> ub(u.data(), u.data() + u.size());
      const Eigen::VectorXd vm = s_.tissue().elementVonMises();
      tissue_->beginStep(t);
      tissue_->pointData("displacement", ub, 3, "m");
      tissue_->cellData("von_mises", std::vector<double>(vm.data(), vm.data() + vm.size()), 1, "Pa");
      tissue_->endStep();
    }
    if (needle_) {
      s_.needleShape(kShapePoints, line_);
      needle_->beginStep(t);
      needle_->stepPoints(std::vector<double>(line_.data(), line_.data() + line_.size()));
      needle_->endStep();
    }
  }

 private:
  const Session& s_;
  io::FieldSeries* tissue_ = nullptr;
  io::FieldSeries* needle_ = nullptr;
  std::vector<double> reference_;
  Eigen::Matrix3Xd line_;
};

// Extremes tracked through the run.
struct Extremes {
  double peak = 0.0, peakDepth = 0.0, maxDepth = 0.0;
  Eigen::Vector2d maxDefl = Eigen::Vector2d::Zero();
  std::vector<double> punctures;
  void track(const StepResult& o) {
    if (o.punctured_now) punctures.push_back(o.depth);
    if (o.axial_force > peak) { peak = o.axial_force; peakDepth = o.depth; }
    for (int j = 0; j < 2; ++j)
      if (std::abs(o.tip_deflection[j]) > std::abs(maxDefl[j])) maxDefl[j] = o.tip_deflection[j];
    maxDepth = std::max(maxDepth, o.depth);
  }
};

// The tets for the linear-range check (realtime/linear_range.hpp): all, or those with a node on
// the needle path (where the shaft's loads act and the strains peak; cheap enough for every sample).
realtime::SimplexStrains tetStrains(const Session& s, bool pathOnly) {
  const auto& mesh = s.mesh();
  std::vector<char> onPath(static_cast<std::size_t>(mesh.nodes()), 0);
  for (const auto& p : s.tissue().path())
    for (int n : p.nodes) onPath[static_cast<std::size_t>(n)] = 1;
  std::vector<int> tets;
  for (std::size_t e = 0; e + 4 <= mesh.conn.size(); e += 4) {
    bool keep = !pathOnly;
    for (std::size_t a = 0; a < 4; ++a) keep = keep || onPath[static_cast<std::size_t>(mesh.conn[e + a])] != 0;
    if (keep) tets.insert(tets.end(), mesh.conn.begin() + static_cast<std::ptrdiff_t>(e), mesh.conn.begin() + static_cast<std::ptrdiff_t>(e + 4));
  }
  return {3, mesh.X, std::move(tets)};
}

class Realtime3dRun {
 public:
  Realtime3dRun(const Scenario& sc, ResultSink& sink, const RunOptions& options)
      : sc_(sc), sink_(sink), options_(options), cfg_(realtime3dConfig(sc)), session_(timed(setup_s_, [this] { announceSetUp(); return Session(cfg_); })),
        motion_(sc.insertion), dt_(sc.model.time_step),
        cadence_(motion_.duration(), dt_, sc.output.interval, sc.model.realtime3d.field_interval), forces_(true, engineColumns()),
        inclusions_(sc.tissue.inclusions, cfg_.frame),
        markers_(3, [this](int node) { return session_.tissue().nodeDisplacement(node); }),
        shape_({{"time", "s"}, {"arc_length", "m"}, {"x", "m"}, {"y", "m"}, {"z", "m"}}),
        pathStrains_(tetStrains(session_, true)) {
    forces_.reserve(cadence_.rows());
    if (cadence_.fieldEvery > 0) fields_ = std::make_unique<Fields3d>(sink_, session_, sc_.tissue);
    placeMarkers();
  }

  void run() {
    record(0.0, motion_.at(0.0), StepResult{});
    if (fields_) fields_->write(0.0);
    Progress progress("realtime3d", options_.progress);
    const auto run0 = std::chrono::steady_clock::now();
    for (long long k = 1; k <= cadence_.steps; ++k) {
      const double t = cadence_.timeOf(k);
      const MotionState m = motion_.at(t);
      // The bevel's turn from the frame's orientation (axial_angle starts at bevel_orientation),
      // and the insert segments' spinning (duty cycling).
      const double roll = m.axial_angle - sc_.insertion.bevel_orientation + motion_.spinAngle(t);
      const BasePose pose = session_.poseAtDepth(m.depth, 0.0, 0.0, m.plane_angle, 0.0, roll);
      const StepResult& o = session_.step(pose, dt_);
      ext_.track(o);
      if (cadence_.sample(k)) record(t, m, o);
      if (cadence_.sample(k)) range_.check(pathStrains_.measure(session_.displacement()), o.depth, sink_);
      if (fields_ && cadence_.field(k)) fields_->write(t);
      if ((k & 1023) == 0 || stopRequested())  // a stop is seen at the next step, however long the steps
        progress.update(static_cast<double>(k) / static_cast<double>(cadence_.steps));
    }
    progress.finish();
    run_s_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - run0).count();
    range_.check(tetStrains(session_, false).measure(session_.displacement()), session_.last().depth, sink_);  // every tet
    addShape(motion_.duration());
  }

  void finish() {
    reportResults();
    plotAxialForces(forces_.table(), sc_, sink_);
    plotDeflection();
    markers_.plot(sink_);
    writeNotes();
    inclusions_.report(sink_);
    sink_.table("forces", forces_.release());
    markers_.writeTable(sink_);
    sink_.table("needle_shape", std::move(shape_));
  }

 private:
  // Markers: x = depth from the entry face, y = lateral from the path line through the entry
  // point, z = from the insertion plane; each in the tet holding it (linear shape functions).
  void placeMarkers() {
    for (const auto& spec : sc_.model.realtime3d.markers) {
      const Eigen::Vector3d p = cfg_.frame.entry + Eigen::Vector3d(spec.x, spec.y, spec.z) + session_.cornerShift();
      const TetPoint at = locateInTets(session_.mesh(), p);
      if (at.element < 0)
        throw SolverError(fmt::format("realtime3d: marker {} lies outside the tissue mesh", spec.name));
      MarkerPoint m;
      m.name = spec.name;
      for (int a = 0; a < 4; ++a) {
        m.nodes[static_cast<std::size_t>(a)] = session_.mesh().conn[static_cast<std::size_t>(4 * at.element + a)];
        m.weights[static_cast<std::size_t>(a)] = at.weights[a];
      }
      markers_.add(std::move(m));
    }
  }

  // A large block sets up for minutes (factorisation, modes): say so on a terminal.
  void announceSetUp() const {
    const auto& b = cfg_.tissue.block;
    if (!options_.progress || !Progress::stderrIsTerminal()) return;
    fmt::print(stderr, "realtime3d: setting up {} (assembly, factorisation, modes; Ctrl-C stops)\n",
               cfg_.tissue.geometry ? cfg_.tissue.geometry->file
                                    : fmt::format("{} x {} x {} nodes", b.nodes_depth, b.nodes_lateral, b.nodes_height));
  }

  void addShape(double t) {
    Eigen::Matrix3Xd line;
    session_.needleShape(kShapePoints, line);
    for (int k = 0; k < kShapePoints; ++k)
      shape_.addRow({t, cfg_.needle.length * k / (kShapePoints - 1), line(0, k), line(1, k), line(2, k)});
  }

  void record(double t, const MotionState& m, const StepResult& o) {
    results::NeedleForces f;
    f.time = t;
    f.depth = t == 0.0 ? m.depth : o.depth;
    f.velocity = m.velocity;
    f.force_total = o.axial_force;
    f.force_lateral = o.lateral_force;
    const Eigen::Vector3d tip = t == 0.0 ? cfg_.frame.onAxis(m.depth) : o.tip_position;
    f.tip_x = tip.x();
    f.tip_y = tip.y();
    f.tip_z = tip.z();
    f.tip_deflection = o.tip_deflection[0];
    // Markers at the output interval only: off the path the reduced back-end rebuilds its
    // residual field by a sparse solve.
    markers_.addRow(t);
    markers_.trackExtremes();
    forces_.add(f, {o.stiffness_force, o.cutting_force, o.friction_force, o.force.x(), o.force.y(), o.force.z(),
                    o.out_of_plane_force, o.tip_deflection[1], o.tip_load[0], o.tip_load[1],
                    static_cast<double>(o.phase), static_cast<double>(o.coupled), static_cast<double>(o.sticking)});
    if (inclusions_.empty()) return;
    Eigen::Matrix3Xd line;  // the tip and the needle's direction there, for the targets' miss distance
    session_.needleShape(kShapePoints, line);
    inclusions_.tip(line.col(kShapePoints - 1), line.col(kShapePoints - 1) - line.col(kShapePoints - 2));
    std::vector<Eigen::Vector3d> u;
    for (std::size_t i = 0; i < sc_.tissue.inclusions.size(); ++i) u.push_back(session_.tissue().regionDisplacement(i));
    inclusions_.add(t, f.depth, u);
  }

  void reportResults() {
    const StepResult& last = session_.last();
    sink_.result("max_tip_deflection", ext_.maxDefl[0], "m", "elastic tip deflection along lateral (y) of largest magnitude");
    sink_.result("max_tip_deflection_z", ext_.maxDefl[1], "m", "elastic tip deflection out of plane (z) of largest magnitude");
    sink_.result("final_tip_deflection", last.tip_deflection[0], "m", "elastic lateral tip deflection at the end");
    sink_.result("final_tip_deflection_z", last.tip_deflection[1], "m", "elastic out-of-plane tip deflection at the end");
    sink_.result("peak_force", ext_.peak, "N", "largest axial force on the needle (resisting insertion)");
    warnZeroForce(sc_, ext_.peak, sink_);
    sink_.result("peak_force_depth", ext_.peakDepth, "m", "tip depth at the peak force");
    sink_.result("final_force", last.axial_force, "N", "axial force on the needle at the end");
    sink_.result("max_depth", ext_.maxDepth, "m", "deepest tip position along the reference axis");
    if (cfg_.tissue.follow_tip) {
      const Eigen::Vector3d u = session_.tipDisplacement();
      for (int c = 0; c < 3; ++c)
        sink_.result(std::string("tip_tissue_displacement_") + "xyz"[c], u[c], "m",
                     "path follow_tip: the tissue's displacement at the tip at the end (the tip is the channel's end moved by it)");
    }
    for (std::size_t i = 0; i < ext_.punctures.size(); ++i)
      sink_.result(i == 0 ? std::string("puncture_depth") : fmt::format("puncture_depth_{}", i + 1), ext_.punctures[i],
                   "m", i == 0 ? "tip depth at puncture (eq 3.16 threshold)" : "tip depth at a layer boundary's puncture");
    markers_.reportResults(sink_);
    sink_.result("steps_per_second", run_s_ > 0 ? cadence_.steps / run_s_ : 0.0, "1/s", "session steps per wall-clock second");
  }

  void plotDeflection() {
    const io::Table& f = forces_.table();
    io::Plot defl{"Tip deflection against time", "time [s]", "elastic tip deflection [mm]", {}};
    defl.series.push_back({"lateral (y)", f.column("time"), realtimeMm(f.column("tip_deflection")), false, false});
    defl.series.push_back({"out of plane (z)", f.column("time"), realtimeMm(f.column("tip_deflection_z")), false, true});
    sink_.plot(std::move(defl));
  }

  void writeNotes() {
    realtime::reportLinearRange(range_, " (the elements on the needle path, and all at the end)", sink_);
    const auto& b = cfg_.tissue.block;
    const auto& m = session_.mesh();
    const std::string mesh = cfg_.tissue.geometry ? fmt::format("the tet mesh of {} ({} nodes", cfg_.tissue.geometry->file, m.nodes())
                                                  : fmt::format("a tetrahedral block ({} x {} x {} nodes", b.nodes_depth, b.nodes_lateral, b.nodes_height);
    sink_.note(fmt::format(
        "Real-time 3D FE model (seed 003 sections 3.1-3.5) on {}, {} tets, {} free DOFs, {} back-end); the shaft "
        "couples at {} points {:g} mm apart embedded in the tets; Newmark dt = {:g} ms, Rayleigh alpha = {:g} 1/s, "
        "beta = {:g} s; needle EI = {:.4g} N m^2 bending in two planes. {} steps in {:.3g} s ({:.3g} steps/s; setup "
        "{:.3g} s). docs/models/realtime3d.md.",
        mesh, m.elements(), session_.tissue().dynamics().freeDofs(), realtimeBackendName(session_.tissue().dynamics().backend()),
        session_.tissue().path().size(), cfg_.tissue.coupling_spacing * 1e3, dt_ * 1e3, cfg_.tissue.rayleigh_alpha,
        cfg_.tissue.rayleigh_beta, cfg_.needle.EI, cadence_.steps, run_s_, run_s_ > 0 ? cadence_.steps / run_s_ : 0.0, setup_s_));
    if (cfg_.tissue.follow_tip)
      sink_.note(fmt::format("The path follows the channel the tip cuts (path: follow_tip): the tip turns towards the "
                             "bevel at {:.4g} 1/m (kinematic bevel-tip model, Webster et al. 2006), each path point is "
                             "embedded where the tip reaches it and holds the shaft there.",
                             cfg_.tissue.channel_curvature));
    for (const auto& L : sc_.tissue.layers)
      if (L.material.law != "linear") {
        sink_.note("The tissue law is linearised: realtime3d uses its small-strain moduli (initial shear and bulk).");
        break;
      }
  }

  const Scenario& sc_;
  ResultSink& sink_;
  RunOptions options_;
  SessionConfig cfg_;
  double setup_s_ = 0.0, run_s_ = 0.0;
  Session session_;
  MotionProfile motion_;
  double dt_;
  RunCadence cadence_;
  results::ForcesTable forces_;
  results::InclusionMotion inclusions_;
  RealtimeMarkers markers_;
  io::Table shape_;
  realtime::SimplexStrains pathStrains_;
  realtime::LinearRangeWarning range_{"realtime3d"};
  std::unique_ptr<Fields3d> fields_;
  Extremes ext_;
};

}  // namespace

// The needle couples to the tissue at the path points, coupling_spacing apart: a step must not
// carry the tip past them.
StepPlan realtime3dStepPlan(const Scenario& sc) {
  realtime3dConfig(sc);  // the engine's own refusals (layers, inclusions), for check as for run
  const auto& m = sc.model.realtime3d;
  StepPlan p = fixedStepPlan(sc, "realtime3d");
  p.spacing = m.coupling_spacing;
  p.spacingName = "the spacing of the path points (model.realtime3d.coupling_spacing)";
  // the tissue's nodes: the imported mesh's, else the block's (far face and four sides held) (run_cost.hpp)
  const auto* imported = sc.tissue.geometry ? sc.tissue.geometry->mesh.get() : nullptr;
  const double nodes = imported ? imported->nodes() : double(m.nodes_depth) * m.nodes_lateral * m.nodes_height;
  const double freeDofs = imported ? 3.0 * imported->nodes()
                                   : 3.0 * (m.nodes_depth - 1) * (m.nodes_lateral - 2) * (m.nodes_height - 2);
  double deepest = 0.0;  // the most needle points coupled at once
  for (const MotionSegment& seg : sc.insertion.segments) deepest = std::max(deepest, seg.to_depth);
  run_cost::costRealtime(p, m.solver, 3, nodes, freeDofs, deepest / m.coupling_spacing);
  return p;
}

void runRealtime3d(const Scenario& sc, ResultSink& sink, const RunOptions& options) {
  runRealtimeEngine<Realtime3dRun>(sc, sink, options, realtime3dStepPlan(sc));
}

}  // namespace needlesim::engines
