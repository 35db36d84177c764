#include "needlesim/engines/realtime2d/realtime2d_engine.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>

#include "needlesim/core/progress.hpp"
#include "needlesim/engines/realtime/linear_range.hpp"
#include "needlesim/engines/realtime/markers.hpp"
#include "needlesim/engines/realtime/run_report.hpp"
#include "needlesim/engines/realtime/scenario_config.hpp"
#include "needlesim/engines/realtime2d/imported_mesh.hpp"
#include "needlesim/engines/run_cost.hpp"
#include "needlesim/engines/step_guard.hpp"
#include "needlesim/insertion/motion_profile.hpp"
#include "needlesim/io/field_series.hpp"
#include "needlesim/mesh/volume_mesh.hpp"
#include "needlesim/results/forces_table.hpp"
#include "needlesim/results/inclusion_motion.hpp"
#include "needlesim/results/layer_boundaries.hpp"
#include "needlesim/tissue/regions.hpp"

namespace needlesim::engines {

using namespace realtime2d;

namespace {

// A tissue point in its grid cell: the cell's corners and their bilinear shape functions.
MarkerPoint locate(const Mesh& mesh, const MarkerSpec& spec, double path_y) {
  const double x = spec.x, y = path_y + spec.y;
  auto cell = [](const std::vector<double>& c, double v) {
    auto it = std::upper_bound(c.begin(), c.end(), v);
    int i = static_cast<int>(it - c.begin()) - 1;
    return std::clamp(i, 0, static_cast<int>(c.size()) - 2);
  };
  const int i = cell(mesh.xs, x), j = cell(mesh.ys, y);
  const double s = std::clamp((x - mesh.xs[static_cast<std::size_t>(i)]) /
                                  (mesh.xs[static_cast<std::size_t>(i + 1)] - mesh.xs[static_cast<std::size_t>(i)]),
                              0.0, 1.0);
  const double t = std::clamp((y - mesh.ys[static_cast<std::size_t>(j)]) /
                                  (mesh.ys[static_cast<std::size_t>(j + 1)] - mesh.ys[static_cast<std::size_t>(j)]),
                              0.0, 1.0);
  MarkerPoint m;
  m.name = spec.name;
  m.nodes = {mesh.node(i, j), mesh.node(i + 1, j), mesh.node(i + 1, j + 1), mesh.node(i, j + 1)};
  m.weights = {(1 - s) * (1 - t), s * (1 - t), s * t, (1 - s) * t};
  return m;
}

// Field cells: the quads, or the triangles of an imported triangle mesh (collapsed quads a, b, c, c).
std::vector<int> cells(const Mesh& mesh) {
  if (!mesh.triangles) return std::vector<int>(mesh.quads.data(), mesh.quads.data() + mesh.quads.size());
  std::vector<int> c;
  for (int e = 0; e < mesh.elementCount(); ++e)
    for (int a = 0; a < 3; ++a) c.push_back(mesh.quads(a, e));
  return c;
}

// "21 x 31 nodes" of the generated block, or the imported mesh's nodes and elements.
std::string meshSize(const Mesh& mesh, const Scenario& sc) {
  if (mesh.structured()) return fmt::format("{} x {} nodes", mesh.nx, mesh.ny);
  return fmt::format("an imported mesh of {} nodes and {} {} ({})", mesh.nodeCount(), mesh.elementCount(),
                     mesh.triangles ? "triangles (collapsed quads)" : "quadrilaterals", sc.tissue.geometry->file);
}

std::vector<io::Column> engineColumns() {
  return {{"force_stiffness", "N"}, {"force_cutting", "N"}, {"force_friction", "N"},
          {"torque", "N m"},        {"tip_load", "N"},      {"tip_angle", "rad"},
          {"phase", "1"},           {"coupled_nodes", "1"}, {"sticking_nodes", "1"}};
}

std::vector<double> mm(std::vector<double> v) { return realtimeMm(std::move(v)); }

// Every element's corner triangles, for the linear-range check (realtime/linear_range.hpp).
realtime::SimplexStrains elementStrains(const Mesh& mesh) {
  std::vector<std::array<int, 4>> quads;
  for (int e = 0; e < mesh.elementCount(); ++e) quads.push_back({mesh.quads(0, e), mesh.quads(1, e), mesh.quads(2, e), mesh.quads(3, e)});
  return {2, std::vector<double>(mesh.nodes.data(), mesh.nodes.data() + mesh.nodes.size()), realtime::quadCornerTriangles(quads)};
}

constexpr int kShapePoints = 41;

// One run of a scenario: set up, step through the insertion profile, record, report.
class Realtime2dRun {
 public:
  Realtime2dRun(const Scenario& sc, ResultSink& sink, const RunOptions& options)
      : sc_(sc), sink_(sink), options_(options), cfg_(realtime2dConfig(sc)), session_(timed(setup_s_, [this] { return Session(cfg_); })),
        motion_(sc.insertion), dt_(sc.model.time_step),
        cadence_(motion_.duration(), dt_, sc.output.interval, sc.model.realtime2d.field_interval),
        forces_(true, engineColumns()), inclusions_(sc.tissue.inclusions, cfg_.frame),
        markers_(2, [this](int node) { return nodeDisplacement3(node); }),
        shape_({{"time", "s"}, {"arc_length", "m"}, {"x", "m"}, {"y", "m"}}), strains_(elementStrains(session_.mesh())) {
    forces_.reserve(cadence_.rows());
    placeMarkers();
    if (cadence_.fieldEvery > 0) openFields();
  }

  void run() {
    recordStart();
    Progress progress("realtime2d", options_.progress);
    const auto run0 = std::chrono::steady_clock::now();
    for (long long k = 1; k <= cadence_.steps; ++k) {
      const double t = cadence_.timeOf(k);
      const MotionState m = motion_.at(t);
      // The bevel's turn from the frame's orientation (axial_angle starts at bevel_orientation).
      const BasePose pose = session_.poseAtDepth(m.depth, 0.0, m.plane_angle, m.axial_angle - sc_.insertion.bevel_orientation);
      const StepResult& o = session_.step(pose, dt_);
      track(o);
      const bool sample = cadence_.sample(k);
      if (sample || (k & 15) == 0) markers_.trackExtremes();  // extremes every 16 steps, rows at the output interval
      if (sample) record(t, m, o);
      if (sample) range_.check(strains_.measure(session_.displacement()), o.depth, sink_);
      if (cadence_.field(k)) writeFields(t);
      if ((k & 1023) == 0 || stopRequested())  // a stop is seen at the next step, however long the steps
        progress.update(static_cast<double>(k) / static_cast<double>(cadence_.steps));
    }
    progress.finish();
    if (cadence_.fieldEvery == 0) addShape(motion_.duration());  // the final needle shape is always reported
    run_s_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - run0).count();
  }

  void finish() {
    reportResults();
    plotForces();
    plotShape();
    markers_.plot(sink_);
    writeNotes();
    inclusions_.report(sink_);
    sink_.table("forces", forces_.release());
    markers_.writeTable(sink_);
    sink_.table("needle_shape", std::move(shape_));
  }

 private:
  // Markers: x = depth from the entry face, y = lateral from the path line (mesh coordinates).
  void placeMarkers() {
    const double path_y = session_.entryPoint().y() + session_.cornerShift().y();
    for (const auto& spec : sc_.model.realtime2d.markers) markers_.add(locate(session_.mesh(), spec, path_y));
  }

  Eigen::Vector3d nodeDisplacement3(int node) const {
    const Eigen::Vector2d u = session_.tissue().nodeDisplacement(node);
    return {u.x(), u.y(), 0.0};
  }

  // ParaView series in the centred tissue frame: the tissue (the reference nodes, region, displacement,
  // von Mises) and the needle centre line.
  void openFields() {
    const Mesh& mesh = session_.mesh();
    tissueSeries_ = sink_.fields("tissue", 2);
    needleSeries_ = sink_.fields("needle", 2);
    const Eigen::Matrix2Xd centred = mesh.nodes.colwise() - session_.cornerShift();
    reference_.assign(centred.data(), centred.data() + centred.size());
    if (tissueSeries_) {  // the reference points (Warp By Vector deforms them) and the region of every cell
      const std::vector<int> conn = cells(mesh);
      tissueSeries_->setMesh(reference_, mesh.triangles ? io::CellType::Triangle : io::CellType::Quad, conn);
      tissueSeries_->meshCellLabels("region", tissue::cellRegions(sc_.tissue, reference_, 2, conn, mesh.triangles ? 3 : 4),
                                    tissue::regionLegend(sc_.tissue));
    }
    session_.needleShape(kShapePoints, needle_);
    std::vector<int> conn;
    for (int k = 0; k + 1 < kShapePoints; ++k) { conn.push_back(k); conn.push_back(k + 1); }
    if (needleSeries_)
      needleSeries_->setMesh(std::vector<double>(needle_.data(), needle_.data() + needle_.size()), io::CellType::Line,
                             conn);
    ubuf_.resize(static_cast<std::size_t>(2 * mesh.nodeCount()));
    vm_.resize(static_cast<std::size_t>(mesh.elementCount()));
  }

  void addShape(double t) {
    session_.needleShape(kShapePoints, needle_);
    for (int k = 0; k < kShapePoints; ++k)
      shape_.addRow({t, cfg_.needle.length * k / (kShapePoints - 1), needle_(0, k), needle_(1, k)});
  }

  void writeFields(double t) {
    addShape(t);
    if (tissueSeries_) writeTissueField(t);
    if (needleSeries_) {
      needleSeries_->beginStep(t);
      needleSeries_->stepPoints(std::vector<double>(needle_.data(), needle_.data() + needle_.size()));
      needleSeries_->endStep();
    }
  }

  void writeTissueField(double t) {
    const auto& u = session_.displacement();
    std::copy(u.data(), u.data() + u.size(), ubuf_.begin());
    const Eigen::Matrix4Xd sig = session_.tissue().elementStresses();
    for (Eigen::Index e = 0; e < sig.cols(); ++e) {  // von Mises of (sxx, syy, szz, sxy)
      const double a = sig(0, e), b = sig(1, e), z = sig(3, e), xy = sig(2, e);
      vm_[static_cast<std::size_t>(e)] =
          std::sqrt(0.5 * ((a - b) * (a - b) + (b - z) * (b - z) + (z - a) * (z - a)) + 3.0 * xy * xy);
    }
    tissueSeries_->beginStep(t);
    tissueSeries_->pointData("displacement", ubuf_, 2, "m");
    tissueSeries_->cellData("von_mises", vm_, 1, "Pa");
    tissueSeries_->endStep();
  }

  void recordStart() {
    const MotionState m0 = motion_.at(0.0);
    StepResult o0;
    o0.depth = m0.depth;
    o0.tip_position = session_.entryPoint() + m0.depth * cfg_.frame.axial.head<2>();
    record(0.0, m0, o0);
    if (cadence_.fieldEvery > 0) writeFields(0.0);
  }

  void record(double t, const MotionState& m, const StepResult& o) {
    results::NeedleForces f;
    f.time = t;
    f.depth = o.depth;
    f.velocity = m.velocity;
    f.force_total = o.axial_force;
    f.force_lateral = o.lateral_force;
    f.tip_x = o.tip_position.x();
    f.tip_y = o.tip_position.y();
    f.tip_z = 0.0;
    f.tip_deflection = o.tip_deflection;
    forces_.add(f, {o.stiffness_force, o.cutting_force, o.friction_force, o.torque, o.tip_load, o.tip_angle,
                    static_cast<double>(o.phase), static_cast<double>(o.coupled), static_cast<double>(o.sticking)});
    markers_.addRow(t);
    recordInclusions(t, o.depth);
  }

  void recordInclusions(double t, double depth) {
    if (inclusions_.empty()) return;
    std::vector<Eigen::Vector3d> u;
    for (std::size_t i = 0; i < sc_.tissue.inclusions.size(); ++i) {
      const Eigen::Vector2d d = session_.tissue().regionDisplacement(i);
      u.emplace_back(d.x(), d.y(), 0.0);
    }
    inclusions_.add(t, depth, u);
  }

  void track(const StepResult& o) {
    if (o.punctured_now) punctures_.push_back(o.depth);
    if (o.axial_force > peak_) { peak_ = o.axial_force; peakDepth_ = o.depth; }
    if (std::abs(o.tip_deflection) > std::abs(maxDefl_)) { maxDefl_ = o.tip_deflection; maxDeflDepth_ = o.depth; }
    maxDepth_ = std::max(maxDepth_, o.depth);
  }

  void reportResults() {
    const StepResult& last = session_.last();
    sink_.result("max_tip_deflection", maxDefl_, "m", "elastic lateral tip deflection of largest magnitude");
    sink_.result("max_tip_deflection_depth", maxDeflDepth_, "m", "tip depth at the largest tip deflection");
    sink_.result("final_tip_deflection", last.tip_deflection, "m", "elastic lateral tip deflection at the end");
    sink_.result("peak_force", peak_, "N", "largest axial force on the needle (resisting insertion)");
    warnZeroForce(sc_, peak_, sink_);
    sink_.result("peak_force_depth", peakDepth_, "m", "tip depth at the peak force");
    sink_.result("final_force", last.axial_force, "N", "axial force on the needle at the end");
    sink_.result("max_depth", maxDepth_, "m", "deepest tip position along the reference axis");
    if (!punctures_.empty())
      sink_.result("puncture_depth", punctures_.front(), "m", "tip depth at puncture (eq 3.16 threshold)");
    for (std::size_t i = 1; i < punctures_.size(); ++i)
      sink_.result(fmt::format("puncture_depth_{}", i + 1), punctures_[i], "m",
                   fmt::format("tip depth at the {}. puncture (a layer boundary, eq 3.16)", i + 1));
    sink_.result("final_torque", last.torque, "N m", "moment of the tissue forces about the needle base at the end");
    markers_.reportResults(sink_);
  }

  void plotForces() {
    const io::Table& f = forces_.table();
    plotAxialForces(f, sc_, sink_);
    io::Plot defl{"Tip deflection against time", "time [s]", "elastic tip deflection [mm]", {}};
    defl.series.push_back({"tip deflection", f.column("time"), mm(f.column("tip_deflection")), false, false});
    sink_.plot(std::move(defl));
  }

  void plotShape() {
    io::Plot shp{"Needle shape", "x (depth) [mm]", "y (lateral) [mm]", {}};
    const double tEnd = shape_.at(shape_.rows() - 1, 0);
    std::vector<double> x, y;
    for (std::size_t i = 0; i < shape_.rows(); ++i)
      if (shape_.at(i, 0) == tEnd) { x.push_back(shape_.at(i, 2) * 1e3); y.push_back(shape_.at(i, 3) * 1e3); }
    shp.series.push_back({fmt::format("t = {:g} s", tEnd), x, y, false, false});
    sink_.plot(std::move(shp));
  }

  void writeNotes() {
    realtime::reportLinearRange(range_, "", sink_);
    const auto& r = sc_.model.realtime2d;
    const Mesh& mesh = session_.mesh();
    sink_.note(fmt::format(
        "Real-time 2D FE model of seed 003 sections 3.1-3.5: {} ({} free DOFs, {} back-end), Newmark "
        "dt = {:g} ms, Rayleigh alpha = {:g} 1/s, beta = {:g} s; Euler-Bernoulli needle EI = {:.4g} N m^2. {} steps "
        "in {:.3g} s ({:.3g} steps/s on this machine; setup {:.3g} s). docs/models/realtime2d.md.",
        meshSize(mesh, sc_), session_.tissue().freeDofs(), realtimeBackendName(session_.tissue().backend()), dt_ * 1e3,
        cfg_.tissue.rayleigh_alpha, cfg_.tissue.rayleigh_beta, cfg_.needle.EI, cadence_.steps, run_s_,
        run_s_ > 0 ? cadence_.steps / run_s_ : 0.0, setup_s_));
    bool hyper = false, prony = false;
    for (const auto& L : sc_.tissue.layers) {
      hyper = hyper || L.material.law != "linear";
      prony = prony || !L.material.prony.empty();
    }
    for (const auto& I : sc_.tissue.inclusions) hyper = hyper || I.material.law != "linear";
    if (hyper) sink_.note("The tissue law is linearised: realtime2d uses its small-strain moduli (initial shear and bulk).");
    if (prony && !r.relaxation) sink_.note("Prony terms of the material are not used (model.realtime2d.relaxation: off).");
    if (prony && r.relaxation)
      sink_.note("Tissue relaxation: one Prony series relaxes the whole stiffness (QLV, materials/viscoelastic.hpp); "
                 "docs/models/realtime2d.md.");
    if (r.stiffening_factor != 1.0 && r.stiffening_radius > 0.0)
      sink_.note(fmt::format("Stiffening around the needle (seed 003 section 3.5 item 4): E x {:g} within {:g} mm of the path line.",
                             r.stiffening_factor, r.stiffening_radius * 1e3));
    if (sc_.tissue.layers.size() > 1)
      sink_.note("Layers: materials, cutting and friction change at the layer boundaries; each boundary the needle "
                 "reaches is punctured by eq 3.16 with the layer's material and puncture force.");
    if (!sc_.tissue.inclusions.empty())
      sink_.note("Inclusions: bonded, as material discs (their section in the insertion plane) of the 2D mesh; "
                 "inclusions.csv holds the mean displacement of their elements' nodes.");
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
  realtime::SimplexStrains strains_;
  realtime::LinearRangeWarning range_{"realtime2d"};
  io::FieldSeries* tissueSeries_ = nullptr;
  io::FieldSeries* needleSeries_ = nullptr;
  Eigen::Matrix2Xd needle_{2, kShapePoints};
  std::vector<double> ubuf_, vm_;
  std::vector<double> reference_;  // tissue nodes at rest in the field frame
  double peak_ = 0.0, peakDepth_ = 0.0, maxDefl_ = 0.0, maxDeflDepth_ = 0.0, maxDepth_ = 0.0;
  std::vector<double> punctures_;
};

}  // namespace

// The needle couples to the tissue at the mesh's path nodes, evenly spaced
// along the depth (mesh.cpp): a step must not carry the tip past them.
StepPlan realtime2dStepPlan(const Scenario& sc) {
  const SessionConfig cfg = realtime2dConfig(sc);  // the engine's own refusals (layers, inclusions), for check as for run
  const auto& g = sc.tissue.geometry;
  const auto& m = sc.model.realtime2d;
  if (!g) {  // the block: its far face and sides held (run_cost.hpp)
    StepPlan p = realtimeStepPlan(sc, "realtime2d", m.nodes_depth);
    run_cost::costRealtime(p, m.solver, 2, m.nodes_depth * m.nodes_lateral,
                           2.0 * (m.nodes_depth - 1) * (m.nodes_lateral - 2));
    return p;
  }
  // An imported mesh: the closest two path nodes (imported_mesh.hpp).
  const auto path = importedPath(*g, sc.tissue.width, cfg.frame.entry.head<2>(), cfg.frame.axial.head<2>());
  StepPlan p = fixedStepPlan(sc, "realtime2d");
  p.spacing = sc.tissue.length;
  for (std::size_t i = 1; i < path.size(); ++i) p.spacing = std::min(p.spacing, path[i].s - path[i - 1].s);
  p.spacingName = "the closest path nodes of the imported mesh (" + g->file + ")";
  run_cost::costRealtime(p, m.solver, 2, g->mesh->nodes(), 2.0 * g->mesh->nodes());
  return p;
}

void runRealtime2d(const Scenario& sc, ResultSink& sink, const RunOptions& options) {
  runRealtimeEngine<Realtime2dRun>(sc, sink, options, realtime2dStepPlan(sc));
}

}  // namespace needlesim::engines
