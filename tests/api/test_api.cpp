// The public C++ API (needlesim/needlesim.hpp) as a program outside the project uses it:
// this test program links only the shared library needlesim::needlesim.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>

#include <unistd.h>

#include "needlesim/needlesim.hpp"

namespace api = needlesim::api;
namespace fs = std::filesystem;

namespace {

const fs::path kExamples = fs::path(NEEDLESIM_SOURCE_DIR) / "examples";

// Seed 003 eq 5.1 (section 5.1, 10 wt% gelatin, 18 G): force on the needle with `length` [m]
// of shaft in the tissue at speed v [m/s]: cutting + (C_p + b_p v) length.
double eq51(double length, double v) { return 0.04335 + length * (3.791 + 285.053 * v); }

// The message of the api error `call` throws (and that it is of type E).
template <class E, class F>
std::string messageOf(F&& call) {
  try {
    call();
  } catch (const E& e) {
    return e.what();
  }
  ADD_FAILURE() << "expected an exception";
  return "";
}

fs::path freshTemp(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("needlesim_api_test_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

// The realtime2d thesis scenario cut short (insert to `to`) on a coarser mesh (11 x 15
// nodes: a quick set-up), with a forces row every step.
api::Scenario shortRealtime2d(const std::string& to) {
  return api::Scenario::fromFile(kExamples / "realtime2d/thesis_gelatin_18G_3mms.yaml")
      .with({{"insertion.profile[0].insert.to", to},
             {"output.interval", "1 ms"},
             {"model.realtime2d.nodes_depth", "11"},
             {"model.realtime2d.nodes_lateral", "15"}});
}

}  // namespace

TEST(ApiScenario, ReadsFileAndDefault) {
  const auto s = api::Scenario::fromFile(kExamples / "gelatin_18G_3mms.yaml");
  EXPECT_EQ(s.name(), "gelatin_18G_3mms");
  EXPECT_EQ(s.engine(), "lumped");
  // 70 mm in and 75 mm out at 3 mm/s, and a 5 s pause.
  EXPECT_NEAR(s.duration(), 70.0 / 3.0 + 5.0 + 75.0 / 3.0, 1e-9);
  EXPECT_NE(s.yaml().find("C_p: 3.791 N/m"), std::string::npos);
  EXPECT_EQ(api::Scenario::builtIn().name(), "gelatin_18G_3mms");
  EXPECT_EQ(api::Scenario::fromYaml(s.yaml()).duration(), s.duration());
}

TEST(ApiRun, LumpedExitForceMatchesSeed003Eq51) {
  const api::Results r = api::run(api::Scenario::fromFile(kExamples / "gelatin_18G_3mms.yaml"));
  EXPECT_EQ(r.status, "complete");
  const api::Value& exit = r.value("exit_force");
  EXPECT_EQ(exit.unit, "N");
  EXPECT_NEAR(exit.value, eq51(0.055, 0.003), 2e-3 * eq51(0.055, 0.003));
  const api::Table& forces = r.table("forces");
  EXPECT_EQ(forces.unit("force_total"), "N");
  EXPECT_GT(forces.rows(), 100u);
  EXPECT_EQ(forces.column("time").size(), forces.rows());
  EXPECT_TRUE(r.folder.empty());
  EXPECT_TRUE(r.warnings.empty());
}

TEST(ApiRun, WithChangesTheSpeed) {
  const auto fast = api::Scenario::builtIn().with("insertion.profile[0].insert.speed", "10 mm/s");
  EXPECT_NE(fast.yaml().find("10 mm/s"), std::string::npos);
  EXPECT_NEAR(api::run(fast).value("exit_force").value, eq51(0.055, 0.010), 2e-3);
}

// Scenario::with resolves the scenario's relative data paths (tissue.geometry.file), and
// relative paths among the values, from the scenario file's folder, not the current one.
TEST(ApiScenario, WithResolvesRelativePathsFromTheScenarioFolder) {
  const fs::path here = fs::current_path();
  const fs::path elsewhere = freshTemp("with_paths");
  fs::current_path(elsewhere);
  const auto base = api::Scenario::fromFile(kExamples / "realtime2d/imported_block.yaml");  // file: imported_block.geo
  std::string varied, again;
  try {
    varied = base.with("insertion.profile[0].insert.to", "10 mm").yaml();
    again = base.with({{"tissue.geometry.file", "imported_block.geo"}, {"insertion.profile[0].insert.to", "12 mm"}})
                .with("insertion.profile[0].insert.to", "14 mm")
                .yaml();
  } catch (const api::InputError& e) {
    ADD_FAILURE() << e.what();
  }
  fs::current_path(here);
  fs::remove_all(elsewhere);
  const std::string geometry = (kExamples / "realtime2d" / "imported_block.geo").lexically_normal().string();
  EXPECT_NE(varied.find(geometry), std::string::npos) << varied;
  EXPECT_NE(again.find(geometry), std::string::npos) << again;
}

TEST(ApiRun, ToAFolderWritesTablesAndFieldFiles) {
  const fs::path dir = freshTemp("folder");
  const auto sc = shortRealtime2d("2 mm").with("model.realtime2d.field_interval", "0.5 s");
  const api::Results r = api::run(sc, dir / "run");
  EXPECT_EQ(r.status, "complete");
  EXPECT_EQ(r.folder, dir / "run");
  EXPECT_TRUE(fs::exists(r.folder / "summary.json"));
  ASSERT_EQ(r.fieldFiles.size(), 2u);
  EXPECT_EQ(r.fieldFiles[0].filename(), "needle.xdmf");
  EXPECT_EQ(r.fieldFiles[1].filename(), "tissue.xdmf");
  // The same tables as in memory.
  const api::Results m = api::run(sc);
  EXPECT_EQ(r.table("forces").column("force_total"), m.table("forces").column("force_total"));
  EXPECT_EQ(r.value("peak_force").value, m.value("peak_force").value);
  // An existing results folder is replaced only when asked.
  const std::string exists = messageOf<api::Error>([&] { api::run(sc, dir / "run"); });
  EXPECT_NE(exists.find("already exists"), std::string::npos) << exists;
  EXPECT_EQ(api::run(sc, dir / "run", api::RunSettings{.overwrite = true}).status, "complete");
  fs::remove_all(dir);
}

TEST(ApiSession, LumpedStepsMatchSeed003Eq51) {
  api::Session s(api::Scenario::fromFile(kExamples / "gelatin_18G_3mms.yaml"));
  EXPECT_EQ(s.engine(), "lumped");
  const double v = 1e-3, dt = 1e-3;
  for (int k = 0; k <= 20000; ++k) s.step(k * v * dt, dt);  // 20 mm at 1 mm/s, 1 kHz
  const api::State& st = s.state();
  EXPECT_NEAR(st.axial_force, eq51(0.020, v), 1e-3);
  EXPECT_NEAR(st.axial_force, st.stiffness_force + st.cutting_force + st.friction_force, 1e-15);
  EXPECT_NEAR(st.cutting_force, 0.04335, 1e-12);
  EXPECT_EQ(st.phase, "cutting");
  EXPECT_NEAR(st.time, 20001 * dt, 1e-9);
  EXPECT_DOUBLE_EQ(st.tip_x, 0.020);
  s.reset();
  EXPECT_EQ(s.state().time, 0.0);
  EXPECT_EQ(s.state().phase, "outside");
}

TEST(ApiSession, Realtime2dStepsGiveTheEngineRunsForces) {
  const auto sc = shortRealtime2d("8 mm");
  const api::Results run = api::run(sc);
  const api::Table& f = run.table("forces");
  const auto& depth = f.column("depth");
  ASSERT_EQ(f.rows(), 3001u);  // one row per 1 ms step over 9 mm at 3 mm/s
  api::Session s(sc);
  EXPECT_EQ(s.engine(), "realtime2d");
  for (std::size_t k = 1; k < f.rows(); ++k) {
    const api::State& st = s.step(depth[k], 1e-3);
    ASSERT_NEAR(st.axial_force, f.column("force_total")[k], 1e-9) << "row " << k;
    ASSERT_NEAR(st.lateral_force, f.column("force_lateral")[k], 1e-9) << "row " << k;
    ASSERT_NEAR(st.tip_deflection, f.column("tip_deflection")[k], 1e-12) << "row " << k;
    ASSERT_NEAR(st.tip_y, f.column("tip_y")[k], 1e-12) << "row " << k;
  }
  EXPECT_GT(s.state().axial_force, 0.04335);  // cutting and friction once inside
  EXPECT_EQ(s.state().phase, "cutting");
  // 11 x 15 nodes; the needle shape runs from the base to the tip.
  EXPECT_EQ(s.nodePositions().size(), 2u * 11 * 15);
  EXPECT_EQ(s.nodeDisplacements().size(), 2u * 11 * 15);
  const auto shape = s.needleShape(11);
  ASSERT_EQ(shape.size(), 22u);
  EXPECT_NEAR(shape[20], s.state().tip_x, 1e-9);
  EXPECT_NEAR(shape[21], s.state().tip_y, 1e-9);
}

// What a viewer draws (needlesim serve): the surface as triangles in z = 0, the field per
// vertex with 3 components and |u|, the needle's centre line in 3D; lumped: the block's plane.
TEST(ApiSession, SurfaceFieldAndNeedleForAViewer) {
  api::Session s(shortRealtime2d("8 mm"));
  for (int k = 1; k <= 2000; ++k) s.step(4e-6 * k, 1e-3);
  const api::Surface surface = s.surface();
  ASSERT_EQ(surface.vertices.size(), 3u * 11 * 15);
  EXPECT_EQ(surface.triangles.size(), 6u * 10 * 14);  // two triangles per quad
  const auto nodes = s.nodePositions();
  for (std::size_t i = 0; i < 11 * 15; ++i) {
    EXPECT_EQ(surface.vertices[3 * i], nodes[2 * i]);
    EXPECT_EQ(surface.vertices[3 * i + 2], 0.0);
  }
  api::SurfaceField field;
  s.surfaceField(field);
  const auto u = s.nodeDisplacements();
  ASSERT_EQ(field.displacement.size(), surface.vertices.size());
  ASSERT_EQ(field.scalar.size(), 11u * 15);
  double largest = 0.0;
  for (std::size_t i = 0; i < 11 * 15; ++i) {
    EXPECT_EQ(field.displacement[3 * i + 1], u[2 * i + 1]);
    EXPECT_DOUBLE_EQ(field.scalar[i], std::hypot(u[2 * i], u[2 * i + 1]));
    largest = std::max(largest, field.scalar[i]);
  }
  EXPECT_GT(largest, 1e-5);  // the needle has pushed the tissue
  const auto line = s.needleCentreLine(11);
  ASSERT_EQ(line.size(), 33u);
  EXPECT_NEAR(line[30], s.state().tip_x, 1e-9);
  EXPECT_NEAR(line[31], s.state().tip_y, 1e-9);

  // an imported triangle mesh (collapsed quads a, b, c, c): one triangle each, the needle steps in
  api::Session imported(api::Scenario::fromFile(kExamples / "realtime2d" / "imported_block.yaml"));
  for (int k = 1; k <= 500; ++k) imported.step(1e-5 * k, 1e-3);
  const api::Surface triangles = imported.surface();
  EXPECT_EQ(triangles.triangles.size() % 3, 0u);
  for (std::size_t t = 0; t < triangles.triangles.size(); t += 3) {
    EXPECT_NE(triangles.triangles[t + 1], triangles.triangles[t + 2]);
    EXPECT_NE(triangles.triangles[t], triangles.triangles[t + 2]);
  }
  EXPECT_EQ(triangles.vertices.size() / 3, imported.nodePositions().size() / 2);
  EXPECT_GT(imported.state().axial_force, 0.0);  // cutting at 5 mm

  api::Session lumped(api::Scenario::fromFile(kExamples / "gelatin_18G_3mms.yaml"));
  lumped.step(0.01, 1e-3);
  EXPECT_EQ(lumped.surface().triangles.size(), 6u);
  api::SurfaceField still;
  lumped.surfaceField(still);
  EXPECT_EQ(still.displacement, std::vector<double>(12, 0.0));
  const auto straight = lumped.needleCentreLine(2);
  EXPECT_DOUBLE_EQ(straight[3], 0.01);  // the tip at the depth
  EXPECT_THROW(lumped.needleCentreLine(1), api::InputError);
}

namespace {
double largestDifference(const std::vector<double>& a, const std::vector<double>& b) {
  double d = a.size() == b.size() ? 0.0 : std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < std::min(a.size(), b.size()); ++i) d = std::max(d, std::abs(a[i] - b[i]));
  return d;
}
double largest(const std::vector<double>& a) {
  double m = 0.0;
  for (double v : a) m = std::max(m, std::abs(v));
  return m;
}
}  // namespace

// A viewer's field in two parts (needlesim serve computes it off the physics thread): the field
// computed from a snapshot is the one surfaceField gave at the snapshot's step, to round-off, for
// every engine and back-end, though the session has stepped on; a snapshot of another mesh, or
// none, is refused.
// The inclusions for a viewer: the scenario's target (layered_target.yaml: a 3 mm vessel 40 mm
// deep, 3 mm to +y) and the surface vertices of its material, the nodes of the elements whose
// centre lies in it: each within the radius and one element diameter (the longest triangle edge)
// of its axis, the vertex nearest the axis among them. An imported tissue names its file.
TEST(ApiSession, InclusionsAndTheirRegionForAViewer) {
  api::Session s(api::Scenario::fromFile(kExamples / "realtime2d" / "layered_target.yaml"));
  const std::vector<api::Inclusion> inclusions = s.inclusions();
  ASSERT_EQ(inclusions.size(), 1u);
  const api::Inclusion& vessel = inclusions[0];
  EXPECT_EQ(vessel.name, "target");
  EXPECT_EQ(vessel.shape, "cylinder");
  EXPECT_TRUE(vessel.target);
  EXPECT_NEAR(vessel.x, 0.040, 1e-12);
  EXPECT_NEAR(vessel.y, 0.003, 1e-12);
  EXPECT_NEAR(vessel.radius, 0.003, 1e-12);
  const api::Surface surface = s.surface();
  EXPECT_EQ(surface.geometry, "");
  const auto& v = surface.vertices;
  const auto fromAxis = [&](int n) { return std::hypot(v[3 * n] - vessel.x, v[3 * n + 1] - vessel.y); };
  double diameter = 0.0;
  for (std::size_t t = 0; t < surface.triangles.size(); t += 3)
    for (std::size_t a = 0; a < 3; ++a) {
      const int p = surface.triangles[t + a], q = surface.triangles[t + (a + 1) % 3];
      diameter = std::max(diameter, std::hypot(v[3 * p] - v[3 * q], v[3 * p + 1] - v[3 * q + 1]));
    }
  ASSERT_FALSE(vessel.region.empty());
  for (const int n : vessel.region) EXPECT_LE(fromAxis(n), vessel.radius + diameter) << n;
  int nearest = 0;
  for (int n = 1; n < static_cast<int>(v.size() / 3); ++n)
    if (fromAxis(n) < fromAxis(nearest)) nearest = n;
  EXPECT_NE(std::find(vessel.region.begin(), vessel.region.end(), nearest), vessel.region.end());

  api::Session imported(api::Scenario::fromFile(kExamples / "realtime2d" / "imported_block.yaml"));
  EXPECT_NE(imported.surface().geometry.find("imported_block.geo"), std::string::npos);
  ASSERT_EQ(imported.inclusions().size(), 1u);
  EXPECT_EQ(imported.inclusions()[0].shape, "mesh");
  api::Session lumped(api::Scenario::fromFile(kExamples / "gelatin_18G_3mms.yaml"));
  EXPECT_TRUE(lumped.inclusions().empty());
}

TEST(ApiSession, FieldFromASnapshotIsTheFieldOfItsStep) {
  const api::Scenario block = api::Scenario::fromFile(kExamples / "realtime3d/quick_block.yaml")
                                  .with({{"model.realtime3d.nodes_depth", "7"},
                                         {"model.realtime3d.nodes_lateral", "5"},
                                         {"model.realtime3d.nodes_height", "5"}});
  const std::vector<std::pair<std::string, api::Scenario>> cases = {
      {"realtime3d reduced", block.with("model.realtime3d.solver", "reduced")},
      {"realtime3d direct", block.with("model.realtime3d.solver", "direct")},
      {"realtime3d modal", block.with("model.realtime3d.solver", "modal")},
      {"realtime2d", shortRealtime2d("20 mm")},
      {"lumped", api::Scenario::fromFile(kExamples / "gelatin_18G_3mms.yaml")}};
  for (const auto& [name, scenario] : cases) {
    api::Session s(scenario);
    for (int k = 1; k <= 600; ++k) s.step(1e-5 * k, 1e-3);  // 6 mm in
    api::FieldSnapshot snapshot;
    EXPECT_TRUE(snapshot.empty());
    s.snapshotField(snapshot);
    EXPECT_FALSE(snapshot.empty());
    api::SurfaceField then;
    s.surfaceField(then);
    for (int k = 601; k <= 800; ++k) s.step(1e-5 * k, 1e-3);  // on to 8 mm
    api::SurfaceField fromSnapshot, now;
    s.surfaceField(snapshot, fromSnapshot);
    s.surfaceField(now);
    const double scale = largest(then.displacement);
    if (name != "lumped") EXPECT_GT(scale, 1e-6) << name;
    EXPECT_LE(largestDifference(fromSnapshot.displacement, then.displacement), 1e-12 * scale) << name;
    EXPECT_LE(largestDifference(fromSnapshot.scalar, then.scalar), 1e-12 * scale) << name;
    EXPECT_EQ(fromSnapshot.scalarName, then.scalarName);
    if (name != "lumped") EXPECT_GT(largestDifference(now.displacement, then.displacement), 1e-3 * scale) << name;
  }
  api::Session small(shortRealtime2d("2 mm")), other(block);
  api::SurfaceField field;
  EXPECT_THROW(small.surfaceField(api::FieldSnapshot{}, field), api::InputError);
  api::FieldSnapshot ofTheBlock;
  other.snapshotField(ofTheBlock);
  const std::string wrong = messageOf<api::InputError>([&] { small.surfaceField(ofTheBlock, field); });
  EXPECT_NE(wrong.find("another mesh"), std::string::npos) << wrong;
}

// realtime3d through the public Session: the engine run's forces step by step, 3D arrays, the
// tilt out of the plane (refused by the 2D engines).
TEST(ApiSession, Realtime3dStepsGiveTheEngineRunsForces) {
  const auto sc = api::Scenario::fromFile(kExamples / "realtime3d/quick_block.yaml")
                      .with({{"insertion.profile[0].insert.to", "8 mm"}, {"model.realtime3d.field_interval", "0 s"}, {"output.interval", "0 s"}});
  const api::Results run = api::run(sc);
  const api::Table& f = run.table("forces");
  api::Session s(sc);
  EXPECT_EQ(s.engine(), "realtime3d");
  EXPECT_EQ(s.dimension(), 3);
  const auto& depth = f.column("depth");
  for (std::size_t k = 1; k <= 900; ++k) {  // the insertion to 8 mm at 10 mm/s (then the bevel turns)
    s.step(depth[k], 1e-3);
    ASSERT_NEAR(s.state().axial_force, f.column("force_total")[k], 1e-9) << "row " << k;
    ASSERT_NEAR(s.state().tip_z, f.column("tip_z")[k], 1e-12) << "row " << k;
  }
  const std::size_t nodes = 11u * 9 * 9;
  EXPECT_EQ(s.nodePositions().size(), 3 * nodes);
  EXPECT_EQ(s.nodeDisplacements().size(), 3 * nodes);
  EXPECT_EQ(s.needleShape(5).size(), 15u);
  // the viewer's surface: the block's boundary, closed: (2 x 10 x 8 + 2 x 10 x 8 + 2 x 8 x 8)
  // quad faces of two triangles, every triangle's nodes on the block's boundary
  const api::Surface surface = s.surface();
  EXPECT_EQ(surface.vertices, s.nodePositions());
  ASSERT_EQ(surface.triangles.size() % 3, 0u);
  EXPECT_EQ(surface.triangles.size() / 3, 2u * (2 * 10 * 8 + 2 * 10 * 8 + 2 * 8 * 8));
  api::SurfaceField field;
  s.surfaceField(field);
  EXPECT_EQ(field.displacement, s.nodeDisplacements());
  EXPECT_EQ(s.needleCentreLine(5), s.needleShape(5));
  EXPECT_EQ(s.state().phase, "cutting");
  const api::State& tilted = s.step(api::Command{depth[900], 0.0, 0.0, 0.0, 0.01}, 1e-3);
  EXPECT_TRUE(std::isfinite(tilted.out_of_plane_force));
  api::Session flat(shortRealtime2d("2 mm"));
  auto tilt = messageOf<api::InputError>([&] { flat.step(api::Command{0.001, 0.0, 0.0, 0.0, 0.1}, 1e-3); });
  EXPECT_NE(tilt.find("tilt"), std::string::npos) << tilt;
}

TEST(ApiErrors, InputErrorsKeepTheirText) {
  const auto base = api::Scenario::builtIn();
  auto missing = messageOf<api::InputError>([] { api::Scenario::fromFile("no_such_scenario.yaml"); });
  EXPECT_NE(missing.find("no_such_scenario.yaml"), std::string::npos) << missing;
  EXPECT_NE(missing.find("does not exist"), std::string::npos) << missing;

  auto path = messageOf<api::InputError>([&] { base.with("tissue.frictoin.C_p", "3 N/m"); });
  EXPECT_NE(path.find("tissue.frictoin.C_p"), std::string::npos) << path;
  EXPECT_NE(path.find("friction"), std::string::npos) << path;

  try {
    base.with("tissue.friction.C_p", "-1 N/m");
    ADD_FAILURE() << "negative friction accepted";
  } catch (const api::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("-1 N/m"), std::string::npos) << e.what();
    EXPECT_EQ(e.field(), "tissue.friction.C_p");
    EXPECT_GT(e.line(), 0);
  }

  auto yaml = messageOf<api::InputError>([] { api::Scenario::fromYaml("tissue: {block: 3}\n", "mine.yaml"); });
  EXPECT_NE(yaml.find("mine.yaml"), std::string::npos) << yaml;
}

TEST(ApiErrors, SessionArguments) {
  const auto lumped = api::Scenario::builtIn();
  api::Session s(lumped);
  auto dt0 = messageOf<api::InputError>([&] { s.step(0.0, 0.0); });
  EXPECT_NE(dt0.find("Session.step(dt)"), std::string::npos) << dt0;
  EXPECT_NE(dt0.find("must be > 0"), std::string::npos) << dt0;
  auto nan = messageOf<api::InputError>([&] { s.step(std::numeric_limits<double>::quiet_NaN(), 1e-3); });
  EXPECT_NE(nan.find("Session.step(depth)"), std::string::npos) << nan;
  EXPECT_NE(nan.find("finite"), std::string::npos) << nan;
  auto steer = messageOf<api::InputError>([&] { s.step(api::Command{0.01, 1e-3, 0.0, 0.0}, 1e-3); });
  EXPECT_NE(steer.find("realtime2d"), std::string::npos) << steer;
  auto shape = messageOf<api::InputError>([&] { s.needleShape(); });
  EXPECT_NE(shape.find("realtime2d"), std::string::npos) << shape;

  const auto explicitScenario = api::Scenario::fromFile(kExamples / "explicit/seed004_bevel_2d.yaml");
  auto engine = messageOf<api::InputError>([&] { api::Session{explicitScenario}; });
  EXPECT_NE(engine.find("explicit"), std::string::npos) << engine;
  EXPECT_NE(engine.find("lumped, realtime2d or realtime3d"), std::string::npos) << engine;

  const api::Results r = api::run(lumped);
  auto column = messageOf<api::InputError>([&] { r.table("forces").column("force"); });
  EXPECT_NE(column.find("force_total"), std::string::npos) << column;
  auto table = messageOf<api::InputError>([&] { r.table("force"); });
  EXPECT_NE(table.find("forces"), std::string::npos) << table;
}

// The step guard of every steppable session (engines/session.hpp), here through the C++ API
// (needlesim serve and its haptic bridge step through it): a tip that moves further than half
// the engine's spacing in one step (from insertion.start_depth on the first), a non-finite
// command and a pose off the tissue are refused with the same text as in Python
// (tests/python/test_errors.py), and the session is left as it was.
TEST(ApiSession, TheStepGuardRefusesLongStepsAndNonFiniteCommands) {
  // lumped: the thinnest layer is the 55 mm block, so at most 27.5 mm per step
  api::Session lumped(api::Scenario::fromFile(kExamples / "gelatin_18G_3mms.yaml"));
  EXPECT_EQ(messageOf<api::InputError>([&] { lumped.step(0.100, 1e-3); }),
            "<session>: Session.step(depth): moves the tip 100 mm in its first step (a Session starts at "
            "insertion.start_depth, 0 mm; only before the tissue (depth <= 0 mm) may it be placed anywhere) (got '0.1'); "
            "allowed: at most 27.5 mm per step (0.5 x the thinnest layer); take smaller steps");
  EXPECT_EQ(messageOf<api::InputError>([&] { lumped.step(std::numeric_limits<double>::quiet_NaN(), 1e-3); }),
            "<session>: Session.step(depth): must be a finite number (got 'nan'); allowed: a tip depth in m");
  EXPECT_EQ(lumped.state().time, 0.0);  // nothing was stepped
  lumped.step(0.020, 1e-3);             // within the guard
  EXPECT_NE(messageOf<api::InputError>([&] { lumped.step(0.050, 1e-3); }).find("moves the tip 30 mm in one step (from 20 mm)"),
            std::string::npos);
  EXPECT_DOUBLE_EQ(lumped.state().depth, 0.020);

  // realtime2d: every argument of the command must be finite, and the tip may not jump
  api::Session fe(shortRealtime2d("8 mm"));
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  const std::pair<api::Command, const char*> bad[] = {{{nan, 0, 0, 0, 0}, "Session.step(depth)"},
                                                      {{0, inf, 0, 0, 0}, "Session.step(lateral)"},
                                                      {{0, 0, nan, 0, 0}, "Session.step(rotation)"},
                                                      {{0, 0, 0, -inf, 0}, "Session.step(roll)"},
                                                      {{0, 0, 0, 0, nan}, "Session.step(tilt)"}};
  for (const auto& [command, field] : bad) {
    const std::string text = messageOf<api::InputError>([&] { fe.step(command, 1e-3); });
    EXPECT_NE(text.find(field), std::string::npos) << text;
    EXPECT_NE(text.find("must be a finite number"), std::string::npos) << text;
  }
  EXPECT_THROW(fe.step(0.0, inf), api::InputError);
  const std::string jump = messageOf<api::InputError>([&] { fe.step(0.030, 1e-3); });
  EXPECT_NE(jump.find("moves the tip 30 mm in its first step"), std::string::npos) << jump;
  EXPECT_NE(jump.find("0.5 x the node spacing"), std::string::npos) << jump;
  const std::string off = messageOf<api::InputError>([&] { fe.step(api::Command{0.0, 1.0, 0.0, 0.0}, 1e-3); });
  EXPECT_NE(off.find("Session.step(lateral)"), std::string::npos) << off;
  EXPECT_NE(off.find("entry face"), std::string::npos) << off;
  EXPECT_EQ(fe.state().time, 0.0);
  for (int k = 1; k <= 10; ++k) fe.step(1e-4 * k, 1e-3);  // the session goes on
  const std::string later = messageOf<api::InputError>([&] { fe.step(0.030, 1e-3); });
  EXPECT_NE(later.find("in one step (from 1 mm)"), std::string::npos) << later;
  EXPECT_NEAR(fe.state().depth, 1e-3, 1e-4);
  EXPECT_NEAR(fe.state().time, 10e-3, 1e-12);
  // the axes each engine takes besides depth (the others are refused)
  EXPECT_TRUE(fe.axes().lateral && fe.axes().rotation && fe.axes().roll);
  EXPECT_FALSE(fe.axes().tilt);
  EXPECT_FALSE(lumped.axes().lateral || lumped.axes().rotation || lumped.axes().roll || lumped.axes().tilt);
}

TEST(ApiFit, PlastisolCompression) {
  api::FitOptions o;
  o.data = {kExamples / "data/plastisol_compression.csv"};
  o.law = "neo-hookean";
  const api::FitResults r = api::fit(o);
  EXPECT_EQ(r.law, "neo-hookean");
  ASSERT_FALSE(r.parameters.empty());
  EXPECT_EQ(r.parameters[0].name, "C10");
  EXPECT_EQ(r.parameters[0].unit, "Pa");
  // The synthetic data: C10 = 3.6 kPa with 1 % noise (examples/data/make_examples.py).
  EXPECT_NEAR(r.parameters[0].value, 3600.0, 0.03 * 3600.0);
  EXPECT_NE(r.table.find("C10"), std::string::npos);
  EXPECT_TRUE(r.folder.empty());

  o.law = "no-such-law";
  auto law = messageOf<api::InputError>([&] { api::fit(o); });
  EXPECT_NE(law.find("neo-hookean"), std::string::npos) << law;
}

TEST(ApiSweep, SmallGridRunsEveryCase) {
  const fs::path dir = freshTemp("sweep");
  std::ofstream(dir / "speeds.yaml") << "scenario: " << (kExamples / "gelatin_18G_3mms.yaml").string()
                                     << "\nname: speeds\nmethod: grid\nvary:\n"
                                        "  - field: insertion.profile[0].insert.speed\n"
                                        "    values: [3 mm/s, 10 mm/s]\n";
  api::SweepOptions o;
  o.out = dir / "study";
  const api::SweepSummary s = api::sweep(dir / "speeds.yaml", o);
  EXPECT_EQ(s.folder, dir / "study");
  EXPECT_EQ(s.cases, 2);
  EXPECT_EQ(s.ran, 2);
  EXPECT_TRUE(s.failed.empty());
  EXPECT_TRUE(fs::exists(s.folder / "study.csv"));
  fs::remove_all(dir);
}

TEST(ApiErrors, SolverErrorsKeepTheirText) {
  // A conditionally stable Newmark integrator (beta < gamma / 2) with a step above its limit.
  const auto unstable = api::Scenario::fromFile(kExamples / "realtime2d/retraction.yaml")
                            .with({{"model.realtime2d.newmark_beta", "0.05"},
                                   {"model.realtime2d.nodes_depth", "11"},
                                   {"model.realtime2d.nodes_lateral", "13"},
                                   {"model.time_step", "5 ms"}});
  auto inRun = messageOf<api::SolverError>([&] { api::run(unstable); });
  EXPECT_NE(inRun.find("stability limit"), std::string::npos) << inRun;
  auto inSession = messageOf<api::SolverError>([&] { api::Session{unstable}; });
  EXPECT_EQ(inSession, inRun);
}
