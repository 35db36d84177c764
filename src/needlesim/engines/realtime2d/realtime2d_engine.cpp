#include "needlesim/engines/realtime2d/realtime2d_engine.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>

#include "needlesim/core/error.hpp"
#include "needlesim/core/progress.hpp"
#include "needlesim/insertion/motion_profile.hpp"
#include "needlesim/io/field_series.hpp"
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

// A tissue point followed through the run: bilinear interpolation in its element.
struct Marker {
  std::string name;
  int nodes[4] = {0, 0, 0, 0};
  double w[4] = {0, 0, 0, 0};
  double max_ux = 0, max_uy = 0;  // signed values of largest magnitude
};

Marker locate(const Mesh& mesh, const MarkerSpec& spec, double path_y) {
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
  Marker m;
  m.name = spec.name;
  const int n[4] = {mesh.node(i, j), mesh.node(i + 1, j), mesh.node(i + 1, j + 1), mesh.node(i, j + 1)};
  const double w[4] = {(1 - s) * (1 - t), s * (1 - t), s * t, (1 - s) * t};
  for (int a = 0; a < 4; ++a) { m.nodes[a] = n[a]; m.w[a] = w[a]; }
  return m;
}

Eigen::Vector2d markerDisplacement(const Tissue& tissue, const Marker& m) {
  Eigen::Vector2d u = Eigen::Vector2d::Zero();
  for (int a = 0; a < 4; ++a)
    if (m.w[a] != 0.0) u += m.w[a] * tissue.nodeDisplacement(m.nodes[a]);
  return u;
}

const char* backendName(Backend b) {
  switch (b) {
    case Backend::Direct: return "direct";
    case Backend::Modal: return "modal";
    case Backend::Reduced: return "reduced";
    default: return "auto";
  }
}

}  // namespace

SessionConfig realtime2dConfig(const Scenario& sc) {
  const auto& r = sc.model.realtime2d;
  SessionConfig c;
  const auto& L0 = sc.tissue.layers.front();
  c.tissue.material = elasticOf(L0.material, r);
  if (sc.tissue.layers.size() > 1) {
    double x = 0.0;
    for (const auto& L : sc.tissue.layers) {
      x += L.thickness;
      c.tissue.layers.emplace_back(x, elasticOf(L.material, r));
      c.layers.push_back({x, L.friction, L.cutting_force});
    }
  }
  c.tissue.mesh.length = sc.tissue.length;
  c.tissue.mesh.width = sc.tissue.width;
  c.tissue.mesh.nodes_depth = r.nodes_depth;
  c.tissue.mesh.nodes_lateral = r.nodes_lateral;
  c.tissue.mesh.grading = r.refinement;
  c.tissue.lumped_mass = r.lumped_mass;
  c.tissue.rayleigh_alpha = r.rayleigh_alpha;  // eq 3.8
  c.tissue.rayleigh_beta = r.rayleigh_beta;
  c.tissue.newmark.gamma = r.newmark_gamma;    // eqs 3.2-3.3
  c.tissue.newmark.beta = r.newmark_beta;
  c.tissue.support_stiffness = r.spring_boundary ? r.spring_stiffness : 0.0;
  if (r.relaxation) c.tissue.prony = L0.material.prony;  // QLV relaxation (one set for the block)
  c.tissue.stiffening_factor = r.stiffening_factor;
  c.tissue.stiffening_radius = r.stiffening_radius;
  c.tissue.backend = r.solver == "direct"    ? Backend::Direct
                     : r.solver == "modal"   ? Backend::Modal
                     : r.solver == "reduced" ? Backend::Reduced
                                             : Backend::Auto;
  const auto& nd = sc.needle;
  c.needle.length = nd.length;
  c.needle.EI = nd.youngs_modulus * std::numbers::pi / 64.0 *
                (std::pow(nd.outer_diameter, 4) - std::pow(nd.inner_diameter, 4));
  c.needle.bevel_angle = nd.bevel_angle;
  // A symmetric (conical, blunt) tip carries no transverse load.
  c.needle.tip_load_ratio = nd.tip == TipType::Bevel ? r.tip_load_ratio : 0.0;
  c.friction = L0.friction;
  c.cutting_force = L0.cutting_force;
  forces::StiffnessLaw law{c.tissue.material.E, c.tissue.material.nu, nd.bevel_angle, sc.insertion.entry_angle};
  // The reader marks a puncture depth with a negative value: convert it by eq 3.16.
  c.puncture_force = L0.puncture_force >= 0.0 ? L0.puncture_force : law.force(-L0.puncture_force);
  c.frame = needle::InsertionFrame::fromInsertion(sc.insertion);
  c.dt = sc.model.time_step;
  if (sc.insertion.entry_angle < 0.25 * std::numbers::pi - 1e-12)
    throw SolverError(fmt::format("realtime2d: entry angle {:g} deg is below the 45 deg the path-node coupling "
                                  "supports (the needle axis must be within 45 deg of the entry-face normal)",
                                  sc.insertion.entry_angle * 180.0 / std::numbers::pi));
  return c;
}

void runRealtime2d(const Scenario& sc, ResultSink& sink, const RunOptions& options) {
  const auto& r = sc.model.realtime2d;
  const SessionConfig cfg = realtime2dConfig(sc);
  const auto wall0 = std::chrono::steady_clock::now();
  Session s(cfg);  // refuses unstable settings with the limit they break
  const double setup_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  const Mesh& mesh = s.mesh();
  MotionProfile motion(sc.insertion);
  const double dt = sc.model.time_step;
  const auto steps = static_cast<long long>(std::ceil(motion.duration() / dt - 1e-9));
  const long long every =
      outputStride(sc.output.interval, dt);
  const long long fieldEvery =
      r.field_interval > 0.0 ? std::max(1LL, std::llround(r.field_interval / dt)) : 0LL;

  std::vector<Marker> markers;
  const double path_y = s.entryPoint().y() + s.cornerShift().y();
  for (const auto& m : r.markers) markers.push_back(locate(mesh, m, path_y));

  io::Table forces({{"time", "s"},
                    {"depth", "m"},
                    {"velocity", "m/s"},
                    {"force_total", "N"},
                    {"force_stiffness", "N"},
                    {"force_cutting", "N"},
                    {"force_friction", "N"},
                    {"force_lateral", "N"},
                    {"torque", "N m"},
                    {"tip_load", "N"},
                    {"tip_x", "m"},
                    {"tip_y", "m"},
                    {"tip_deflection", "m"},
                    {"tip_angle", "rad"},
                    {"phase", "1"},
                    {"coupled_nodes", "1"},
                    {"sticking_nodes", "1"}});
  forces.reserve(static_cast<std::size_t>(steps / every + 2));
  std::vector<io::Column> mcols{{"time", "s"}};
  for (const auto& m : markers) {
    mcols.push_back({m.name + "_ux", "m"});
    mcols.push_back({m.name + "_uy", "m"});
  }
  io::Table markerTable(mcols);
  io::Table shape({{"time", "s"}, {"arc_length", "m"}, {"x", "m"}, {"y", "m"}});

  // ParaView series: the tissue (displacement, von Mises) and the needle centre line.
  io::FieldSeries* tf = fieldEvery > 0 ? sink.fields("tissue", 2) : nullptr;
  io::FieldSeries* nf = fieldEvery > 0 ? sink.fields("needle", 2) : nullptr;
  constexpr int kShapePoints = 41;
  Eigen::Matrix2Xd needle(2, kShapePoints);
  if (tf) {
    const Eigen::Matrix2Xd centred = mesh.nodes.colwise() - s.cornerShift();  // the tissue frame
    std::vector<double> pts(centred.data(), centred.data() + centred.size());
    std::vector<int> conn(mesh.quads.data(), mesh.quads.data() + mesh.quads.size());
    tf->setMesh(pts, io::CellType::Quad, conn);
  }
  if (nf) {
    s.needleShape(kShapePoints, needle);
    std::vector<double> pts(needle.data(), needle.data() + needle.size());
    std::vector<int> conn;
    for (int k = 0; k + 1 < kShapePoints; ++k) { conn.push_back(k); conn.push_back(k + 1); }
    nf->setMesh(pts, io::CellType::Line, conn);
  }
  std::vector<double> ubuf(static_cast<std::size_t>(2 * mesh.nodeCount())),
      vm(static_cast<std::size_t>(mesh.elementCount()));
  auto writeFields = [&](double t) {
    s.needleShape(kShapePoints, needle);
    for (int k = 0; k < kShapePoints; ++k)
      shape.addRow({t, cfg.needle.length * k / (kShapePoints - 1), needle(0, k), needle(1, k)});
    if (tf) {
      const auto& u = s.displacement();
      std::copy(u.data(), u.data() + u.size(), ubuf.begin());
      const Eigen::Matrix4Xd sig = s.tissue().elementStresses();
      for (int e = 0; e < mesh.elementCount(); ++e) {  // von Mises of (sxx, syy, szz, sxy)
        const double a = sig(0, e), b = sig(1, e), z = sig(3, e), xy = sig(2, e);
        vm[static_cast<std::size_t>(e)] =
            std::sqrt(0.5 * ((a - b) * (a - b) + (b - z) * (b - z) + (z - a) * (z - a)) + 3.0 * xy * xy);
      }
      tf->beginStep(t);
      tf->pointData("displacement", ubuf, 2);
      tf->cellData("von_mises", vm, 1);
      tf->endStep();
    }
    if (nf) {
      nf->beginStep(t);
      nf->stepPoints(std::vector<double>(needle.data(), needle.data() + needle.size()));
      nf->endStep();
    }
  };

  Progress progress("realtime2d", options.progress);
  double peak = 0.0, peakDepth = 0.0, maxDefl = 0.0, maxDeflDepth = 0.0, punctureDepth = NAN;
  double maxDepth = 0.0;
  const auto run0 = std::chrono::steady_clock::now();
  auto record = [&](double t, const MotionState& m, const StepResult& o) {
    forces.addRow({t, o.depth, m.velocity, o.axial_force, o.stiffness_force, o.cutting_force, o.friction_force,
                   o.lateral_force, o.torque, o.tip_load, o.tip_position.x(), o.tip_position.y(), o.tip_deflection,
                   o.tip_angle, static_cast<double>(o.phase), static_cast<double>(o.coupled),
                   static_cast<double>(o.sticking)});
    std::vector<double> row{t};
    for (auto& mk : markers) {
      const Eigen::Vector2d u = markerDisplacement(s.tissue(), mk);
      row.push_back(u.x());
      row.push_back(u.y());
    }
    markerTable.addRow(row);
  };
  {
    const MotionState m0 = motion.at(0.0);
    StepResult o0;
    o0.depth = m0.depth;
    o0.tip_position = s.entryPoint() + m0.depth * cfg.frame.axial.head<2>();
    record(0.0, m0, o0);
    if (fieldEvery > 0) writeFields(0.0);
  }
  for (long long k = 1; k <= steps; ++k) {
    const double t = std::min(k * dt, motion.duration());
    const MotionState m = motion.at(t);
    const BasePose pose = s.poseAtDepth(m.depth, 0.0, m.plane_angle, m.axial_angle - sc.insertion.bevel_orientation);
    const StepResult& o = s.step(pose, dt);
    if (o.punctured_now && std::isnan(punctureDepth)) punctureDepth = o.depth;
    if (o.axial_force > peak) { peak = o.axial_force; peakDepth = o.depth; }
    if (std::abs(o.tip_deflection) > std::abs(maxDefl)) { maxDefl = o.tip_deflection; maxDeflDepth = o.depth; }
    maxDepth = std::max(maxDepth, o.depth);
    const bool sample = k % every == 0 || k == steps;
    if (sample || !markers.empty()) {
      for (auto& mk : markers) {  // extremes at every step, rows at the output interval
        if (!sample && (k & 15) != 0) continue;
        const Eigen::Vector2d u = markerDisplacement(s.tissue(), mk);
        if (std::abs(u.x()) > std::abs(mk.max_ux)) mk.max_ux = u.x();
        if (std::abs(u.y()) > std::abs(mk.max_uy)) mk.max_uy = u.y();
      }
    }
    if (sample) record(t, m, o);
    if (fieldEvery > 0 && (k % fieldEvery == 0 || k == steps)) writeFields(t);
    if ((k & 1023) == 0) progress.update(static_cast<double>(k) / static_cast<double>(steps));
  }
  progress.finish();
  if (fieldEvery == 0) {  // the final needle shape is always reported
    s.needleShape(kShapePoints, needle);
    for (int k = 0; k < kShapePoints; ++k)
      shape.addRow({motion.duration(), cfg.needle.length * k / (kShapePoints - 1), needle(0, k), needle(1, k)});
  }
  const double run_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - run0).count();
  const StepResult& last = s.last();

  sink.result("max_tip_deflection", maxDefl, "m", "elastic lateral tip deflection of largest magnitude");
  sink.result("max_tip_deflection_depth", maxDeflDepth, "m", "tip depth at the largest tip deflection");
  sink.result("final_tip_deflection", last.tip_deflection, "m", "elastic lateral tip deflection at the end");
  sink.result("peak_force", peak, "N", "largest axial force on the needle (resisting insertion)");
  sink.result("peak_force_depth", peakDepth, "m", "tip depth at the peak force");
  sink.result("final_force", last.axial_force, "N", "axial force on the needle at the end");
  sink.result("max_depth", maxDepth, "m", "deepest tip position along the reference axis");
  if (!std::isnan(punctureDepth)) sink.result("puncture_depth", punctureDepth, "m", "tip depth at puncture (eq 3.16 threshold)");
  sink.result("final_torque", last.torque, "N m", "moment of the tissue forces about the needle base at the end");
  for (const auto& mk : markers) {
    const Eigen::Vector2d u = markerDisplacement(s.tissue(), mk);
    sink.result("marker_" + mk.name + "_ux_max", mk.max_ux, "m", "largest depth-wise displacement of marker " + mk.name);
    sink.result("marker_" + mk.name + "_uy_max", mk.max_uy, "m", "largest lateral displacement of marker " + mk.name);
    sink.result("marker_" + mk.name + "_ux_final", u.x(), "m", "final depth-wise displacement of marker " + mk.name);
    sink.result("marker_" + mk.name + "_uy_final", u.y(), "m", "final lateral displacement of marker " + mk.name);
  }

  // Plots (mm for lengths).
  auto mm = [](std::vector<double> v) { for (double& x : v) x *= 1e3; return v; };
  const auto depth = mm(forces.column("depth"));
  const auto time = forces.column("time");
  io::Plot byDepth{"Axial force against tip depth", "tip depth [mm]", "force on the needle [N]", {}};
  io::Plot byTime{"Axial force against time", "time [s]", "force on the needle [N]", {}};
  for (auto* p : {&byDepth, &byTime}) {
    const auto& x = p == &byDepth ? depth : time;
    p->series.push_back({"total", x, forces.column("force_total"), false, false});
    p->series.push_back({"stiffness (eq 3.16)", x, forces.column("force_stiffness"), false, true});
    p->series.push_back({"cutting (eq 3.24)", x, forces.column("force_cutting"), false, true});
    p->series.push_back({"friction (eq 3.23)", x, forces.column("force_friction"), false, true});
  }
  sink.plot(std::move(byDepth));
  sink.plot(std::move(byTime));
  io::Plot defl{"Tip deflection against time", "time [s]", "elastic tip deflection [mm]", {}};
  defl.series.push_back({"tip deflection", time, mm(forces.column("tip_deflection")), false, false});
  sink.plot(std::move(defl));
  io::Plot shp{"Needle shape", "x (depth) [mm]", "y (lateral) [mm]", {}};
  {
    const double tEnd = shape.at(shape.rows() - 1, 0);
    std::vector<double> x, y;
    for (std::size_t i = 0; i < shape.rows(); ++i)
      if (shape.at(i, 0) == tEnd) { x.push_back(shape.at(i, 2) * 1e3); y.push_back(shape.at(i, 3) * 1e3); }
    shp.series.push_back({fmt::format("t = {:g} s", tEnd), x, y, false, false});
  }
  sink.plot(std::move(shp));
  if (!markers.empty()) {
    io::Plot paths{"Marker paths", "x displacement [mm]", "y displacement [mm]", {}};
    io::Plot mt{"Marker displacement against time", "time [s]", "displacement [mm]", {}};
    const auto mtime = markerTable.column("time");
    for (const auto& mk : markers) {
      const auto ux = mm(markerTable.column(mk.name + "_ux")), uy = mm(markerTable.column(mk.name + "_uy"));
      paths.series.push_back({mk.name, ux, uy, false, false});
      mt.series.push_back({mk.name + " x", mtime, ux, false, false});
      mt.series.push_back({mk.name + " y", mtime, uy, false, true});
    }
    sink.plot(std::move(paths));
    sink.plot(std::move(mt));
  }
  sink.note(fmt::format(
      "Real-time 2D FE model of seed 003 sections 3.1-3.5: {} x {} nodes ({} free DOFs, {} back-end), Newmark "
      "dt = {:g} ms, Rayleigh alpha = {:g} 1/s, beta = {:g} s; Euler-Bernoulli needle EI = {:.4g} N m^2. {} steps "
      "in {:.3g} s ({:.3g} steps/s on this machine; setup {:.3g} s). docs/models/realtime2d.md.",
      mesh.nx, mesh.ny, s.tissue().freeDofs(), backendName(s.tissue().backend()), dt * 1e3, cfg.tissue.rayleigh_alpha,
      cfg.tissue.rayleigh_beta, cfg.needle.EI, steps, run_s, run_s > 0 ? steps / run_s : 0.0, setup_s));
  bool hyper = false, prony = false;
  for (const auto& L : sc.tissue.layers) {
    hyper = hyper || L.material.law != "linear";
    prony = prony || !L.material.prony.empty();
  }
  if (hyper) sink.note("The tissue law is linearised: realtime2d uses its small-strain moduli (initial shear and bulk).");
  if (prony && !r.relaxation) sink.note("Prony terms of the material are not used (model.realtime2d.relaxation: off).");
  if (prony && r.relaxation)
    sink.note("Tissue relaxation: the first layer's Prony terms relax the whole stiffness (QLV, "
              "materials/viscoelastic.hpp); docs/models/realtime2d.md.");
  if (r.stiffening_factor != 1.0 && r.stiffening_radius > 0.0)
    sink.note(fmt::format("Stiffening around the needle (seed 003 section 3.5 item 4): E x {:g} within {:g} mm of the path line.",
                          r.stiffening_factor, r.stiffening_radius * 1e3));
  if (sc.tissue.layers.size() > 1)
    sink.note("Layers: materials, cutting and friction change at the layer boundaries; only the first layer's "
              "puncture (eq 3.16) is modelled, inner layers are cut without a puncture event.");
  sink.table("forces", std::move(forces));
  if (!markers.empty()) sink.table("markers", std::move(markerTable));
  sink.table("needle_shape", std::move(shape));
}

}  // namespace needlesim::engines
