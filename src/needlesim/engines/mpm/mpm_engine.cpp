// MPM engine: scenario -> MpmSolver -> results (seed 000 sections 3-4).
// Frame: x along the block length from the entry face, y across the width,
// z across the height; the entry point is the centre of the entry face moved
// by insertion.entry_offset along y. docs/models/mpm.md.
#include "needlesim/engines/mpm/mpm_engine.hpp"

#include <Eigen/Geometry>
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <map>
#include <cmath>
#include <numbers>
#include <unordered_map>

#include "needlesim/core/error.hpp"
#include "needlesim/core/progress.hpp"
#include "needlesim/engines/mpm/marker_errors.hpp"
#include "needlesim/insertion/motion_profile.hpp"
#include "needlesim/io/checkpoint.hpp"
#include "needlesim/io/csv_reader.hpp"
#include "needlesim/io/field_series.hpp"

namespace needlesim::engines {

using namespace mpm;

namespace {

FaceBC faceOf(const std::string& s) {
  if (s == "fixed") return FaceBC::Fixed;
  if (s == "roller") return FaceBC::Roller;
  if (s == "non-reflecting") return FaceBC::NonReflecting;
  return FaceBC::Free;
}

// Needle placed with its foremost point at `depth` along the axis and the
// bevel turned by `axial` about the axis.
void placeNeedle(RigidBody& n, const MpmSetup& s, double depth, double axial, double speed) {
  const Vec3 side = s.axis.cross(s.bevel0);
  n.bevelDir = std::cos(axial) * s.bevel0 + std::sin(axial) * side;
  const Vec3 c = s.entry + depth * s.axis;  // axis point level with the tip
  n.point = n.tip == RigidBody::Tip::Bevel ? Vec3(c + n.radius * n.bevelDir) : c;
  n.velocity = speed * s.axis;
}

double vonMises(const Mat3& s) {
  const double a = s(0, 0), b = s(1, 1), c = s(2, 2);
  return std::sqrt(0.5 * ((a - b) * (a - b) + (b - c) * (b - c) + (c - a) * (c - a)) +
                   3.0 * (s(0, 1) * s(0, 1) + s(1, 2) * s(1, 2) + s(0, 2) * s(0, 2)));
}

// Seed 000 eq 35 against a measured force-depth curve: the simulated total force
// is interpolated at each measured depth inside the simulated (first, advancing)
// range of depths.
struct ForceError {
  double rmse = 0.0, mae = 0.0;
  std::size_t n = 0;
  std::vector<double> depth, force;  // the measured points, SI
};

ForceError compareForce(const std::string& file, const std::vector<double>& simDepth,
                        const std::vector<double>& simForce) {
  const io::CsvData csv = io::readCsv(file);
  const int cd = csv.require({"depth", "displacement", "position", "insertion depth"}, units::dim::Length,
                             "the insertion depth");
  const int cf = csv.require({"force", "insertion force", "total force", "force_total"}, units::dim::Force,
                             "the measured force");
  ForceError e;
  e.depth = csv.col(cd);
  e.force = csv.col(cf);
  // The advancing part of the simulation: rows up to the first maximum depth.
  std::vector<double> d, f;
  for (std::size_t i = 0; i < simDepth.size(); ++i) {
    if (!d.empty() && simDepth[i] < d.back()) break;
    if (!d.empty() && simDepth[i] == d.back()) {
      f.back() = simForce[i];
      continue;
    }
    d.push_back(simDepth[i]);
    f.push_back(simForce[i]);
  }
  double s2 = 0.0, s1 = 0.0;
  for (std::size_t k = 0; k < e.depth.size(); ++k) {
    const double x = e.depth[k];
    if (d.size() < 2 || x < d.front() || x > d.back()) continue;
    const auto it = std::upper_bound(d.begin(), d.end(), x);
    const std::size_t j = std::min<std::size_t>(static_cast<std::size_t>(it - d.begin()), d.size() - 1);
    const double t = (x - d[j - 1]) / (d[j] - d[j - 1]);
    const double y = f[j - 1] + t * (f[j] - f[j - 1]);
    const double r = e.force[k] - y;
    s2 += r * r;
    s1 += std::abs(r);
    ++e.n;
  }
  if (e.n > 0) {
    e.rmse = std::sqrt(s2 / static_cast<double>(e.n));
    e.mae = s1 / static_cast<double>(e.n);
  }
  return e;
}

struct Marker {
  std::string name;
  std::size_t particle = 0;
  Vec3 x0 = Vec3::Zero();
  double maxUxy = 0.0;
};

// Numerical fracture (seed 000 section 3.4): pairs of initially neighbouring
// material points (lattice neighbours, distance <= 1.05 spacing) that end up in
// non-adjacent grid cells or more than kSeparation grid cells apart no longer
// interact through the grid: the tissue has separated between them. Each pair
// is reported once, when it first separates, at the position along the needle
// path of its initial midpoint (docs/models/mpm.md).
constexpr double kSeparation = 1.5;  // grid cells

struct FractureTracker {
  std::vector<std::uint32_t> a, b;      // neighbouring pairs
  std::vector<std::uint8_t> separated;
  std::vector<double> pathDepth, radial; // initial midpoint: along the path from the entry point, distance from it
  std::size_t total = 0;
  double onsetDepth = NAN, onsetTime = NAN, deepest = NAN, widest = 0.0;

  void init(const MpmSolver& s, const Vec3& entry, const Vec3& axis) {
    const std::size_t np = s.size();
    const double dp = s.particleSpacing(), reach = 1.05 * dp;
    auto key = [&](const Vec3& x) {
      const auto c = [&](int d) { return static_cast<std::int64_t>(std::floor(x[d] / dp)) & 0x1fffff; };
      return (c(0) << 42) | (c(1) << 21) | c(2);
    };
    std::unordered_map<std::int64_t, std::vector<std::uint32_t>> cells;
    cells.reserve(np);
    for (std::size_t p = 0; p < np; ++p) cells[key(s.position(p))].push_back(static_cast<std::uint32_t>(p));
    for (std::size_t p = 0; p < np; ++p) {
      const Vec3 x = s.position(p);
      for (int i = -1; i <= 1; ++i)
        for (int j = -1; j <= 1; ++j)
          for (int k = -1; k <= 1; ++k) {
            const auto it = cells.find(key(x + dp * Vec3(i, j, k)));
            if (it == cells.end()) continue;
            for (const std::uint32_t q : it->second) {
              if (q <= p || (s.position(q) - x).norm() > reach) continue;
              a.push_back(static_cast<std::uint32_t>(p));
              b.push_back(q);
              const Vec3 m = 0.5 * (x + s.position(q)) - entry;
              const double along = m.dot(axis);
              pathDepth.push_back(along);
              radial.push_back((m - along * axis).norm());
            }
          }
    }
    separated.assign(a.size(), 0);
  }

  // Marks newly separated pairs; adds one row per grid-cell bin of the path.
  void check(const MpmSolver& s, double t, double tipDepth, io::Table& table) {
    const MpmConfig& c = s.config();
    const double h = c.h, lim2 = kSeparation * kSeparation * h * h;
    std::map<long, std::pair<double, int>> bins;  // bin -> (sum of path depths, count)
    for (std::size_t i = 0; i < a.size(); ++i) {
      if (separated[i]) continue;
      const Vec3 xa = s.position(a[i]), xb = s.position(b[i]);
      bool sep = (xa - xb).squaredNorm() > lim2;
      for (int d = 0; d < 3 && !sep; ++d)
        sep = std::abs(std::floor((xa[d] - c.origin[d]) / h) - std::floor((xb[d] - c.origin[d]) / h)) > 1.5;
      if (!sep) continue;
      separated[i] = 1;
      ++total;
      if (std::isnan(onsetDepth)) { onsetDepth = tipDepth; onsetTime = t; }
      if (std::isnan(deepest) || pathDepth[i] > deepest) deepest = pathDepth[i];
      widest = std::max(widest, radial[i]);
      auto& bin = bins[static_cast<long>(std::floor(pathDepth[i] / h))];
      bin.first += pathDepth[i];
      ++bin.second;
    }
    for (const auto& [k, v] : bins)
      table.addRow({t, tipDepth, v.first / v.second, static_cast<double>(v.second), static_cast<double>(total)});
  }
};

}  // namespace

MpmSetup mpmSetup(const Scenario& sc) {
  const MpmModelSpec& m = sc.model.mpm;
  MpmSetup s;
  MpmConfig& c = s.config;
  const double h = m.grid_spacing;
  const Vec3 ext(sc.tissue.length, sc.tissue.width, sc.tissue.height);
  c.h = h;
  c.origin = Vec3::Constant(-m.margin * h);
  for (int d = 0; d < 3; ++d) c.cells[static_cast<std::size_t>(d)] = static_cast<int>(std::ceil(ext[d] / h - 1e-9)) + 2 * m.margin;
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
  for (const auto& L : sc.tissue.layers) s.materials.push_back(MpmMaterial::fromSpec(L.material));

  // Needle axis in the insertion plane (x, y), entry_angle between needle and surface.
  const double th = 0.5 * std::numbers::pi - sc.insertion.entry_angle;
  s.axis = Vec3(std::cos(th), std::sin(th), 0.0);
  s.bevel0 = Vec3(-std::sin(th), std::cos(th), 0.0);
  s.entry = Vec3(0.0, 0.5 * sc.tissue.width + sc.insertion.entry_offset, 0.5 * sc.tissue.height);
  RigidBody& n = s.needle;
  n.kind = RigidBody::Kind::Needle;
  n.tip = sc.needle.tip == TipType::Bevel     ? RigidBody::Tip::Bevel
          : sc.needle.tip == TipType::Conical ? RigidBody::Tip::Conical
                                              : RigidBody::Tip::Blunt;
  n.radius = 0.5 * sc.needle.outer_diameter;
  n.tipAngle = sc.needle.bevel_angle;  // bevel: face to the axis; cone: half-angle
  n.axis = s.axis;
  n.friction = sc.tissue.layers.front().friction.coefficient;  // eq 20
  n.length = sc.needle.length;
  n.surfaceContact = m.cfemp;                 // eqs 22-24
  n.elementSize = m.cfemp_element_size;       // d_e of eq 22
  placeNeedle(n, s, 0.0, sc.insertion.bevel_orientation, 0.0);
  return s;
}

void runMpm(const Scenario& sc, ResultSink& sink, const RunOptions& options) {
  const MpmModelSpec& spec = sc.model.mpm;
  const MpmSetup setup = mpmSetup(sc);
  const auto wall0 = std::chrono::steady_clock::now();
  MpmSolver solver(setup.config);
  for (const auto& mat : setup.materials) solver.addMaterial(mat);
  {
    double x = 0.0;
    int i = 0;
    for (const auto& L : sc.tissue.layers) {
      solver.addBlock(Vec3(x, 0, 0), Vec3(x + L.thickness, sc.tissue.width, sc.tissue.height), spec.particle_spacing,
                      i++, 0);
      x += L.thickness;
    }
  }
  const int needleId = solver.addRigid(setup.needle);
  solver.finalize();
  const double setup_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  const std::size_t np = solver.size();

  MotionProfile motion(sc.insertion);
  const double T = motion.duration();
  const Vec3 axis = setup.axis;
  auto place = [&](double t) {
    const MotionState ms = motion.at(t);
    placeNeedle(solver.rigid(needleId), setup, ms.depth, ms.axial_angle, ms.velocity);
    return ms;
  };

  // Initial particle positions (displacement reference, marker lookup).
  std::vector<double> x0(3 * np);
  for (std::size_t p = 0; p < np; ++p) {
    const Vec3 x = solver.position(p);
    for (int c = 0; c < 3; ++c) x0[3 * p + static_cast<std::size_t>(c)] = x[c];
  }
  std::vector<Marker> markers;
  for (const auto& mk : spec.markers) {
    const Vec3 want = setup.entry + Vec3(mk.x, mk.y, mk.z);
    Marker m;
    m.name = mk.name;
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t p = 0; p < np; ++p) {
      const double d = (solver.position(p) - want).squaredNorm();
      if (d < best) { best = d; m.particle = p; }
    }
    m.x0 = solver.position(m.particle);
    markers.push_back(m);
  }

  // Measured markers (eq 37): read and checked before the run, compared at the end.
  io::CsvData measuredMarkers;
  if (!spec.measured_markers.empty()) {
    measuredMarkers = io::readCsv(spec.measured_markers);
    std::vector<MarkerTrack> names;
    for (const auto& m : markers) names.push_back({m.name, {}, {}});
    compareMarkers(measuredMarkers, {}, names);  // throws on a missing column
  }

  io::Table forces({{"time", "s"},
                    {"depth", "m"},
                    {"velocity", "m/s"},
                    {"force_total", "N"},
                    {"force_tip", "N"},
                    {"force_shaft", "N"},
                    {"force_lateral", "N"},
                    {"contact_nodes", "1"},
                    {"time_step", "s"}});
  io::Table energy({{"time", "s"}, {"depth", "m"}, {"kinetic", "J"}, {"internal", "J"}, {"ke_ie_ratio", "1"}});
  std::vector<io::Column> mcols{{"time", "s"}, {"depth", "m"}};
  for (const auto& m : markers)
    for (const char* k : {"_ux", "_uy", "_uz", "_uxy"}) mcols.push_back({m.name + k, "m"});
  io::Table markerTable(mcols);
  FractureTracker fracture;
  fracture.init(solver, setup.entry, axis);
  io::Table fractureTable({{"time", "s"},
                           {"tip_depth", "m"},
                           {"path_depth", "m"},
                           {"new_pairs", "1"},
                           {"total_pairs", "1"}});

  // ParaView particle series: displacement and von Mises stress.
  io::FieldSeries* fs = spec.field_interval > 0.0 ? sink.fields("particles", 3) : nullptr;
  std::vector<double> pts(3 * np), disp(3 * np), vm(np);
  if (fs) fs->setMesh(x0, io::CellType::Points, {});
  auto writeFields = [&](double t) {
    if (!fs) return;
    for (std::size_t p = 0; p < np; ++p) {
      const Vec3 x = solver.position(p);
      for (int c = 0; c < 3; ++c) {
        const std::size_t i = 3 * p + static_cast<std::size_t>(c);
        pts[i] = x[c];
        disp[i] = x[c] - x0[i];
      }
      vm[p] = vonMises(solver.cauchy(p));
    }
    fs->beginStep(t);
    fs->stepPoints(pts);
    fs->pointData("displacement", disp, 3);
    fs->pointData("von_mises", vm, 1);
    fs->endStep();
  };
  auto recordMarkers = [&](double t, double depth) {
    if (markers.empty()) return;
    std::vector<double> row{t, depth};
    for (auto& m : markers) {
      const Vec3 u = solver.position(m.particle) - m.x0;
      const double uxy = std::hypot(u.x(), u.y());  // eq 36
      m.maxUxy = std::max(m.maxUxy, uxy);
      row.insert(row.end(), {u.x(), u.y(), u.z(), uxy});
    }
    markerTable.addRow(row);
  };

  // Force rows are the impulse averages over the output interval (the contact
  // force of a single explicit step is noisy).
  Vec3 impTot = Vec3::Zero(), impTip = Vec3::Zero(), impShaft = Vec3::Zero();
  double impT = 0.0;
  int contactNodes = 0;
  double peak = 0.0, peakDepth = 0.0, lastForce = 0.0, lastTip = 0.0, lastShaft = 0.0;
  long long steps = 0;
  double dtMin = std::numeric_limits<double>::infinity(), dtMax = 0.0;
  auto axial = [&](const Vec3& f) { return 0.0 - f.dot(axis); };  // resisting insertion = positive

  MotionState ms = place(0.0);
  const double outEvery = sc.output.interval;
  double nextOut = outEvery, nextField = spec.field_interval;
  double nextMarkerDepth = spec.marker_depth_step > 0 ? (std::floor(ms.depth / spec.marker_depth_step) + 1) * spec.marker_depth_step : 0.0;

  // Checkpoints (io/checkpoint.hpp, docs/models/mpm.md "Checkpoints"): the
  // engine's state between two steps (the tables so far, the accumulators of
  // the next output row, the next output times, the markers' and the fracture
  // tracker's records) followed by the solver's. Everything else is set up
  // again from the scenario exactly as in the first run.
  constexpr std::uint32_t kEngineLayout = 1;
  io::Checkpoint* ck = options.checkpoint;
  io::Checkpoint::Series series;
  if (fs) series.emplace_back("particles", fs);
  auto saveCheckpoint = [&] {
    io::BinaryWriter w;
    w.tag("mpm_engine");
    w.pod(kEngineLayout);
    for (const io::Table* t : {&forces, &energy, &markerTable, &fractureTable}) w.table(*t);
    for (const Vec3* v : {&impTot, &impTip, &impShaft})
      for (int d = 0; d < 3; ++d) w.pod((*v)[d]);
    for (const double x : {impT, peak, peakDepth, lastForce, lastTip, lastShaft, dtMin, dtMax, nextOut, nextField,
                           nextMarkerDepth})
      w.pod(x);
    w.pod(static_cast<std::int32_t>(contactNodes));
    w.pod(steps);
    std::vector<double> maxUxy;
    for (const auto& m : markers) maxUxy.push_back(m.maxUxy);
    w.vec(maxUxy);
    w.vec(fracture.separated);
    w.pod(static_cast<std::uint64_t>(fracture.total));
    for (const double x : {fracture.onsetDepth, fracture.onsetTime, fracture.deepest, fracture.widest}) w.pod(x);
    solver.saveState(w);
    ck->write("mpm", w, series, solver.time(), steps);
  };
  auto loadCheckpoint = [&] {
    io::BinaryReader r = ck->load("mpm", series);
    r.tag("mpm_engine");
    if (r.pod<std::uint32_t>() != kEngineLayout) r.fail("holds an mpm engine state of another layout (another version)");
    io::Table* tables[] = {&forces, &energy, &markerTable, &fractureTable};
    for (io::Table* t : tables) {
      io::Table u = r.table();
      bool same = u.columns().size() == t->columns().size();
      for (std::size_t c = 0; same && c < u.columns().size(); ++c) same = u.columns()[c].name == t->columns()[c].name;
      if (!same) r.fail("holds tables with other columns (another set-up)");
      *t = std::move(u);
    }
    for (Vec3* v : {&impTot, &impTip, &impShaft})
      for (int d = 0; d < 3; ++d) r.pod((*v)[d]);
    for (double* x : {&impT, &peak, &peakDepth, &lastForce, &lastTip, &lastShaft, &dtMin, &dtMax, &nextOut, &nextField,
                      &nextMarkerDepth})
      r.pod(*x);
    contactNodes = r.pod<std::int32_t>();
    r.pod(steps);
    const auto maxUxy = r.vec<double>(markers.size(), "markers");
    for (std::size_t i = 0; i < markers.size(); ++i) markers[i].maxUxy = maxUxy[i];
    fracture.separated = r.vec<std::uint8_t>(fracture.a.size(), "fracture pairs");
    fracture.total = static_cast<std::size_t>(r.pod<std::uint64_t>());
    for (double* x : {&fracture.onsetDepth, &fracture.onsetTime, &fracture.deepest, &fracture.widest}) r.pod(*x);
    solver.loadState(r);
    ms = motion.at(std::min(solver.time(), T));
  };
  std::string resumedNote;
  if (ck && ck->resuming()) {
    loadCheckpoint();
    resumedNote = fmt::format(
        "Resumed from the checkpoint at t = {:.9g} s (step {}, depth {:.4g} mm); steps before it ran in an earlier "
        "process.",
        ck->resumedTime(), ck->resumedSteps(), ms.depth * 1e3);
  } else {
    forces.addRow({0.0, ms.depth, ms.velocity, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0});
    energy.addRow({0.0, ms.depth, 0.0, 0.0, 0.0});
    recordMarkers(0.0, ms.depth);
    writeFields(0.0);
  }
  const long long steps0 = steps;

  auto emit = [&](bool stopped) {
    sink.result("peak_force", peak, "N", "largest axial force on the needle (resisting insertion)");
    sink.result("peak_force_depth", peakDepth, "m", "tip depth at the peak force");
    sink.result("final_force", lastForce, "N", "axial force on the needle at the final depth");
    sink.result("final_tip_force", lastTip, "N", "axial force on the tip faces at the final depth");
    sink.result("final_shaft_force", lastShaft, "N", "axial force on the shaft (friction) at the final depth");
    sink.result("final_depth", ms.depth, "m", "tip depth at the end");
    // KE/IE while the internal energy is at least 1 % of its largest value
    // (before that both are round-off and their ratio says nothing).
    const auto ke = energy.column("kinetic"), ie = energy.column("internal");
    const double ieMax = ie.empty() ? 0.0 : *std::max_element(ie.begin(), ie.end());
    double maxRatio = 0.0;
    for (std::size_t i = 0; i < ke.size(); ++i)
      if (ieMax > 0 && ie[i] >= 0.01 * ieMax) maxRatio = std::max(maxRatio, ke[i] / ie[i]);
    sink.result("max_ke_ie", maxRatio, "1",
                "largest kinetic / internal energy while the internal energy is >= 1 % of its maximum (mass "
                "scaling check, eq 28)");
    sink.result("fracture_pairs", static_cast<double>(fracture.total), "1",
                "neighbouring material-point pairs separated into non-adjacent cells or > 1.5 cells apart "
                "(numerical fracture, section 3.4)");
    if (fracture.total > 0) {
      sink.result("fracture_onset_depth", fracture.onsetDepth, "m", "tip depth when the first pair separated");
      sink.result("fracture_onset_time", fracture.onsetTime, "s", "time when the first pair separated");
      sink.result("fracture_deepest", fracture.deepest, "m",
                  "deepest separation along the needle path (initial midpoint of the pair, from the entry point)");
      sink.result("fracture_max_offset", fracture.widest, "m",
                  "largest distance of a separated pair (initial midpoint) from the needle path");
    }
    sink.result("particles", static_cast<double>(np), "1", "material points");
    sink.result("steps", static_cast<double>(steps), "1", "explicit time steps");
    if (steps > 0) {
      sink.result("time_step_min", dtMin, "s", "smallest time step (eqs 25-26)");
      sink.result("time_step_max", dtMax, "s", "largest time step (eqs 25-26)");
    }
    for (const auto& m : markers) {
      const Vec3 u = solver.position(m.particle) - m.x0;
      sink.result("marker_" + m.name + "_uxy_final", std::hypot(u.x(), u.y()), "m",
                  "final in-plane displacement of marker " + m.name + " (eq 36)");
      sink.result("marker_" + m.name + "_uxy_max", m.maxUxy, "m",
                  "largest recorded in-plane displacement of marker " + m.name + " (eq 36)");
    }
    auto mm = [](std::vector<double> v) {
      for (double& x : v) x *= 1e3;
      return v;
    };
    const auto depth = mm(forces.column("depth"));
    io::Plot byDepth{"Insertion force against tip depth", "tip depth [mm]", "axial force on the needle [N]", {}};
    byDepth.series.push_back({"total", depth, forces.column("force_total"), false, false});
    byDepth.series.push_back({"tip", depth, forces.column("force_tip"), false, true});
    byDepth.series.push_back({"shaft (friction)", depth, forces.column("force_shaft"), false, true});
    if (!spec.measured_force.empty() && !stopped) {
      const ForceError e = compareForce(spec.measured_force, forces.column("depth"), forces.column("force_total"));
      byDepth.series.push_back({"measured", mm(e.depth), e.force, true, false});
      if (e.n > 0) {
        sink.result("rmse_force", e.rmse, "N", "RMSE of the total force against the measured curve (eq 35)");
        sink.result("mae_force", e.mae, "N", "MAE of the total force against the measured curve (eq 35)");
        sink.result("measured_points", static_cast<double>(e.n), "1", "measured points inside the simulated depths");
      } else {
        sink.note("The measured force curve has no point inside the simulated depths: no RMSE/MAE.");
      }
    }
    sink.plot(std::move(byDepth));
    io::Plot en{"Kinetic / internal energy", "time [s]", "KE / IE [-]", {}};
    en.series.push_back({"KE / IE", energy.column("time"), energy.column("ke_ie_ratio"), false, false});
    sink.plot(std::move(en));
    if (!markers.empty()) {
      io::Plot mp{"Marker displacement against depth (eq 36)", "tip depth [mm]", "in-plane displacement [mm]", {}};
      const auto md = mm(markerTable.column("depth"));
      for (const auto& m : markers) mp.series.push_back({m.name, md, mm(markerTable.column(m.name + "_uxy")), false, false});
      sink.plot(std::move(mp));
    }
    sink.table("forces", std::move(forces));
    sink.table("energy", std::move(energy));
    if (!spec.measured_markers.empty() && !stopped) {
      // Seed 000 eq 37 against the measured markers.
      std::vector<MarkerTrack> tracks;
      for (const auto& m : markers)
        tracks.push_back({m.name, markerTable.column(m.name + "_ux"), markerTable.column(m.name + "_uy")});
      const auto rows = compareMarkers(measuredMarkers, markerTable.column("depth"), tracks);
      io::Table et({{"depth", "m"}, {"r_max", "m"}, {"r_mean", "m"}, {"r_max_x", "m"}, {"r_max_y", "m"},
                    {"r_mean_x", "m"}, {"r_mean_y", "m"}, {"markers", "1"}});
      double worst = 0.0, worstMean = 0.0;
      for (const auto& r : rows) {
        et.addRow({r.depth, r.rmax, r.rmean, r.rmaxX, r.rmaxY, r.rmeanX, r.rmeanY, static_cast<double>(r.markers)});
        worst = std::max(worst, r.rmax);
        worstMean = std::max(worstMean, r.rmean);
      }
      if (!rows.empty()) {
        sink.result("marker_r_max", worst, "m", "largest r_max of eq 37 over the measured depths");
        sink.result("marker_r_mean", worstMean, "m", "largest r_mean of eq 37 over the measured depths");
        sink.result("marker_measured_depths", static_cast<double>(rows.size()), "1",
                    "measured marker depths inside the simulated depths");
      } else {
        sink.note("The measured markers have no depth inside the simulated depths: no eq 37 errors.");
      }
      sink.table("marker_errors", std::move(et));
    }
    if (!markers.empty()) sink.table("markers", std::move(markerTable));
    sink.table("fracture", std::move(fractureTable));
  };

  Progress progress("mpm", options.progress);
  const auto run0 = std::chrono::steady_clock::now();
  try {
    while (solver.time() < T - 1e-12 * std::max(1.0, T)) {
      ms = place(solver.time());
      const StepReport rep = solver.step();
      ++steps;
      dtMin = std::min(dtMin, rep.dt);
      dtMax = std::max(dtMax, rep.dt);
      const RigidForce& f = solver.rigidForce(needleId);
      impTot += rep.dt * f.total;
      impTip += rep.dt * f.tip;
      impShaft += rep.dt * f.shaft;
      impT += rep.dt;
      contactNodes = std::max(contactNodes, f.contactNodes);
      const double t = solver.time();
      ms = motion.at(std::min(t, T));
      const bool last = !(t < T - 1e-12 * std::max(1.0, T));
      if (outEvery <= 0.0 || t >= nextOut - 1e-12 || last) {
        while (outEvery > 0.0 && nextOut <= t + 1e-12) nextOut += outEvery;
        const Vec3 F = impTot / impT, Ftip = impTip / impT, Fsh = impShaft / impT;
        lastForce = axial(F);
        lastTip = axial(Ftip);
        lastShaft = axial(Fsh);
        const double lateral = (F + lastForce * axis).norm();
        if (lastForce > peak) { peak = lastForce; peakDepth = ms.depth; }
        forces.addRow({t, ms.depth, ms.velocity, lastForce, lastTip, lastShaft, lateral,
                       static_cast<double>(contactNodes), rep.dt});
        energy.addRow({t, ms.depth, rep.kinetic, rep.internal, rep.internal > 0 ? rep.kinetic / rep.internal : 0.0});
        impTot.setZero();
        impTip.setZero();
        impShaft.setZero();
        impT = 0.0;
        contactNodes = 0;
        fracture.check(solver, t, ms.depth, fractureTable);
        if (spec.marker_depth_step <= 0.0) recordMarkers(t, ms.depth);
      }
      if (spec.marker_depth_step > 0.0 && ms.depth >= nextMarkerDepth - 1e-12) {
        recordMarkers(t, ms.depth);
        while (nextMarkerDepth <= ms.depth + 1e-12) nextMarkerDepth += spec.marker_depth_step;
      }
      if (fs && (t >= nextField - 1e-12 || last)) {
        writeFields(t);
        while (nextField <= t + 1e-12) nextField += spec.field_interval;
      }
      if ((steps & 31) == 0)
        progress.update(t / T, fmt::format("depth {:.2f} mm, F {:.3g} N", ms.depth * 1e3, lastForce));
      if (ck && !last && ck->due(steps)) saveCheckpoint();
      if (options.stopAfterSteps > 0 && steps >= options.stopAfterSteps && !last) {
        progress.finish();
        throw RunInterrupted(fmt::format("mpm: stopped after {} steps (test hook RunOptions::stopAfterSteps)", steps));
      }
    }
  } catch (const SolverError&) {
    progress.finish();
    sink.note("The run stopped early (see the error); the results cover the time up to the failure.");
    if (!resumedNote.empty()) sink.note(resumedNote);
    emit(true);
    throw;
  }
  progress.finish();
  const double run_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - run0).count();

  const auto& c = setup.config;
  sink.note(fmt::format(
      "3D MPM of seed 000: {} material points ({:g} mm spacing), grid {} x {} x {} cells of {:g} mm, {} shape "
      "functions{}, {}, FLIP {:g}, k_t = {:g} (eq 26), mass scaling {:g} (eq 28); rigid {} needle R = {:g} mm, "
      "Coulomb friction {:g} ({}). {} steps (dt {:.3g} to {:.3g} ms) in {:.3g} s on {} thread(s), "
      "{:.3g} M particle-steps/s (setup {:.2g} s). Force rows are impulse averages over the output interval. "
      "docs/models/mpm.md.",
      np, spec.particle_spacing * 1e3, c.cells[0], c.cells[1], c.cells[2], c.h * 1e3,
      spec.bspline ? "quadratic B-spline" : "linear", spec.fbar ? " with F-bar" : "", spec.musl ? "MUSL" : "USL", spec.flip, spec.time_step_factor,
      spec.mass_scaling,
      sc.needle.tip == TipType::Bevel ? "bevel" : sc.needle.tip == TipType::Conical ? "conical" : "blunt",
      setup.needle.radius * 1e3, setup.needle.friction,
      spec.cfemp ? "CFEMP particle-to-surface contact with the triangulated needle, eqs 22-24"
                 : "grid contact, eqs 14-21",
      steps, dtMin * 1e3, dtMax * 1e3, run_s, solver.threads(),
      run_s > 0 ? static_cast<double>(steps - steps0) * static_cast<double>(np) / run_s * 1e-6 : 0.0, setup_s));

  if (!markers.empty()) {
    double worst = 0.0;
    for (std::size_t i = 0; i < markers.size(); ++i) {
      const auto& mk = spec.markers[i];
      worst = std::max(worst, (markers[i].x0 - (setup.entry + Vec3(mk.x, mk.y, mk.z))).norm());
    }
    sink.note(fmt::format("Markers follow the material point nearest to each given position (at most {:.3g} mm away).",
                          worst * 1e3));
  }
  bool prony = false, frictionDiffers = false;
  for (const auto& L : sc.tissue.layers) {
    prony = prony || !L.material.prony.empty();
    frictionDiffers = frictionDiffers || L.friction.coefficient != sc.tissue.layers.front().friction.coefficient;
  }
  if (prony) sink.note("Prony terms of the material are not used by mpm (hyperelastic tissue).");
  if (frictionDiffers) sink.note("mpm uses the first layer's Coulomb coefficient for the whole needle.");
  for (const auto& seg : sc.insertion.segments)
    if (seg.kind == MotionSegment::Kind::Rotate && !seg.axial) {
      sink.note("In-plane base rotations are not modelled by mpm: the needle only translates along its axis.");
      break;
    }
  if (!resumedNote.empty()) sink.note(resumedNote);
  emit(false);
}

}  // namespace needlesim::engines
