// realtime3d markers: located in the tet that holds them and read by its linear shape
// functions (engines/realtime/markers.hpp, realtime3d/fe.hpp locateInTets), reachable from
// the scenario (model.realtime3d.markers) with the reader's refusals naming the field.
#include <gtest/gtest.h>

#include <cmath>

#include <Eigen/LU>
#include <map>

#include "needlesim/core/error.hpp"
#include "needlesim/engines/engine.hpp"
#include "needlesim/engines/realtime/markers.hpp"
#include "needlesim/engines/realtime3d/realtime3d_engine.hpp"
#include "needlesim/scenario/reader.hpp"
#include "../support/tet_nodes.hpp"

using namespace needlesim;
using namespace needlesim::realtime3d;

namespace {
struct MemorySink final : ResultSink {
  std::map<std::string, io::Table> tables;
  std::map<std::string, double> results;
  int plots = 0;
  void table(const std::string& name, io::Table t) override { tables[name] = std::move(t); }
  void result(const std::string& key, double v, const std::string&, const std::string&) override { results[key] = v; }
  void plot(io::Plot) override { ++plots; }
  void note(const std::string&) override {}
};

// A coarse gelatin block after 12 mm of insertion at 10 mm/s: a displacement field to read.
Session insertedSession() {
  SessionConfig c = gelatinBlockConfig(11, 7, Backend::Direct);
  c.tissue.block.grading = 3.0;
  c.puncture_force = 0.05;
  Session s(c);
  for (double d = -1e-3; d < 0.012; d += 1e-2 * c.dt) s.step(s.poseAtDepth(d), c.dt);
  return s;
}

engines::RealtimeMarkers readerOf(const Session& s) {
  return engines::RealtimeMarkers(3, [&s](int node) { return s.tissue().nodeDisplacement(node); });
}

engines::MarkerPoint pointAt(const Session& s, const std::string& name, const Eigen::Vector3d& p) {
  const TetPoint at = locateInTets(s.mesh(), p);
  EXPECT_GE(at.element, 0) << name;
  engines::MarkerPoint m;
  m.name = name;
  for (int a = 0; a < 4; ++a) {
    m.nodes[static_cast<std::size_t>(a)] = s.mesh().conn[static_cast<std::size_t>(4 * at.element + a)];
    m.weights[static_cast<std::size_t>(a)] = at.weights[a];
  }
  return m;
}

Eigen::Vector3d nodeAt(const TetMesh& mesh, int n) { return {mesh.coord(n, 0), mesh.coord(n, 1), mesh.coord(n, 2)}; }

const char* kScenario = R"(name: markers3d
tissue:
  block: {length: 40 mm, width: 40 mm, height: 40 mm}
  material: gelatin_10wt
  puncture: {force: 0.05 N}
  cutting: {force: 0.04335 N}
  friction: {C_p: 3.791 N/m, b_p: 285.053 N s/m^2, static_band: 0.1 mm/s}
needle: {outer_diameter: 18 G, length: 100 mm, bevel_angle: 30 deg}
insertion:
  start_depth: -1 mm
  profile:
    - insert: {to: 12 mm, speed: 10 mm/s}
model:
  engine: realtime3d
  time_step: 1 ms
  realtime3d:
    nodes_depth: 11
    nodes_lateral: 9
    nodes_height: 9
    refinement: 3
    field_interval: 0 s
    markers:
      - {name: a, x: 8 mm, y: 4 mm, z: 0 mm}
      - {name: b, x: 6 mm, y: -3 mm, z: 2 mm}
output: {interval: 10 ms}
)";

std::string refusal(const std::string& text) {
  try {
    scenario::readText(text, "markers3d.yaml");
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "expected an InputError";
  return "";
}

std::string withMarkers(const std::string& markers) {
  std::string y = kScenario;
  const auto a = y.find("      - {name: a");
  const auto b = y.find("output:");
  return y.replace(a, b - a, markers);
}
}  // namespace

using needlesim::testing::nearestNode;

// A marker on a mesh node reads that node's displacement (its shape function there is 1).
TEST(Realtime3dMarkers, MarkerOnANodeReadsTheNode) {
  const Session s = insertedSession();
  const int node = nearestNode(s.mesh(), s.tissue().path()[12].X) + 1;  // a free node one grid line beside the path
  auto markers = readerOf(s);
  markers.add(pointAt(s, "on_node", nodeAt(s.mesh(), node)));
  const Eigen::Vector3d u = s.tissue().nodeDisplacement(node);
  ASSERT_GT(u.norm(), 1e-7);
  EXPECT_LT((markers.displacement(0) - u).norm(), 1e-12 * u.norm());
}

// Inside a tet the marker reads the linear interpolation of its corners, N solved here from
// p = sum N_a X_a, sum N_a = 1 (the barycentric coordinates), independently of locateInTets.
TEST(Realtime3dMarkers, MarkerInsideATetReadsTheLinearInterpolation) {
  const Session s = insertedSession();
  const int e = s.mesh().elements() / 2 + 7;
  const Eigen::Matrix<double, 3, 4> X = tetCorners(s.mesh(), e);
  const Eigen::Vector4d wanted(0.1, 0.2, 0.3, 0.4);
  const Eigen::Vector3d p = X * wanted;
  auto markers = readerOf(s);
  markers.add(pointAt(s, "inside", p));
  Eigen::Matrix4d A;
  A.topRows<3>() = X;
  A.row(3).setOnes();
  const Eigen::Vector4d N = A.lu().solve(Eigen::Vector4d(p.x(), p.y(), p.z(), 1.0));
  EXPECT_LT((N - wanted).norm(), 1e-12);
  Eigen::Vector3d u = Eigen::Vector3d::Zero();
  for (int a = 0; a < 4; ++a) u += N[a] * s.tissue().nodeDisplacement(s.mesh().conn[static_cast<std::size_t>(4 * e + a)]);
  ASSERT_GT(u.norm(), 1e-8);
  EXPECT_LT((markers.displacement(0) - u).norm(), 1e-9 * u.norm());
}

// The scenario's markers run through the engine: markers.csv with ux, uy, uz per marker, the
// key results, and a marker beside the path dragged along the insertion (x > 0) by friction.
TEST(Realtime3dMarkers, ScenarioMarkersAreReported) {
  const Scenario sc = scenario::readText(kScenario, "markers3d.yaml");
  ASSERT_EQ(sc.model.realtime3d.markers.size(), 2u);
  EXPECT_DOUBLE_EQ(sc.model.realtime3d.markers[1].z, 2e-3);
  MemorySink out;
  const EngineInfo* engine = findEngine("realtime3d");
  ASSERT_NE(engine, nullptr);
  engine->run(sc, out, RunOptions{false});
  ASSERT_TRUE(out.tables.count("markers"));
  const io::Table& t = out.tables.at("markers");
  for (const char* c : {"time", "a_ux", "a_uy", "a_uz", "b_ux", "b_uy", "b_uz"}) EXPECT_NO_THROW(t.columnIndex(c)) << c;
  EXPECT_EQ(t.rows(), out.tables.at("forces").rows());
  for (const char* k : {"ux", "uy", "uz"})
    for (const char* w : {"max", "final"}) EXPECT_TRUE(out.results.count(std::string("marker_a_") + k + "_" + w)) << k << w;
  EXPECT_GT(out.results.at("marker_a_ux_max"), 0.0);
  // the same displacement, read from one DOF of the reduced back-end and from its full field: round-off apart
  const double last = t.at(t.rows() - 1, t.columnIndex("a_ux"));
  EXPECT_NEAR(out.results.at("marker_a_ux_final"), last, 1e-12 * std::abs(last));
}

// Bad marker input is refused naming the field: outside the block, a name used twice, a
// length without its unit, an unknown key, a missing depth.
TEST(Realtime3dMarkers, BadMarkersAreRefusedNamingTheField) {
  std::string why = refusal(withMarkers("      - {name: a, x: 8 mm, y: 4 mm, z: 25 mm}\n"));
  EXPECT_NE(why.find("model.realtime3d.markers[0].z"), std::string::npos) << why;
  EXPECT_NE(why.find("outside the tissue block"), std::string::npos) << why;
  why = refusal(withMarkers("      - {name: a, x: 48 mm, y: 4 mm}\n"));
  EXPECT_NE(why.find("model.realtime3d.markers[0].x"), std::string::npos) << why;
  why = refusal(withMarkers("      - {name: a, x: 8 mm, y: 4 mm}\n      - {name: a, x: 9 mm, y: 4 mm}\n"));
  EXPECT_NE(why.find("model.realtime3d.markers[1].name"), std::string::npos) << why;
  EXPECT_NE(why.find("two markers"), std::string::npos) << why;
  why = refusal(withMarkers("      - {name: a, x: 8, y: 4 mm}\n"));
  EXPECT_NE(why.find("model.realtime3d.markers[0].x"), std::string::npos) << why;
  why = refusal(withMarkers("      - {name: a, x: 8 mm, y: 4 mm, z: 1 mm, w: 2 mm}\n"));
  EXPECT_NE(why.find("model.realtime3d.markers[0].w"), std::string::npos) << why;
  why = refusal(withMarkers("      - {name: a, y: 4 mm}\n"));
  EXPECT_NE(why.find("model.realtime3d.markers[0].x"), std::string::npos) << why;
}
