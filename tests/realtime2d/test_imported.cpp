// tissue.geometry in realtime2d (engines/realtime2d/imported_mesh.hpp): the generated 20 x 20 mm
// block imported as a Gmsh script of the same 1 mm quadrilateral grid gives the generated
// block's forces (same nodes, elements, path and held sides: round-off apart), in mm as in m;
// Gmsh's unstructured triangles (collapsed quads a, b, c, c) of the block agree with the
// generated grid within that grid's own discretisation change; the collapsed quad passes the
// patch test and matches the constant-strain triangle; what the engine cannot take is refused
// with its field.
#include <gtest/gtest.h>

#include <unistd.h>

#include <Eigen/Dense>
#include <cmath>
#include <filesystem>
#include <fmt/format.h>
#include <fstream>
#include <numbers>
#include <numeric>
#include <string>

#include "needlesim/core/error.hpp"
#include "needlesim/engines/engine.hpp"
#include "needlesim/engines/memory_sink.hpp"
#include "needlesim/engines/realtime2d/fe.hpp"
#include "needlesim/forces/stiffness.hpp"
#include "needlesim/scenario/reader.hpp"
#include "../support/block_script.hpp"

using namespace needlesim;
using namespace needlesim::realtime2d;

namespace {

std::filesystem::path dir() {
  auto d = std::filesystem::temp_directory_path() / ("needlesim_rt2_imported_" + std::to_string(::getpid()));
  std::filesystem::create_directories(d);
  return d;
}

// The generated block's 1 mm grid (21 x 21 nodes, a node row on the path y = 0) as a Gmsh
// script in units of `scale` metres.
void writeBlockScript(const std::string& name, double scale) {
  std::ofstream(dir() / name) << test_support::blockScript(0.020, 20, scale);
}

// The block as Gmsh's unstructured triangles of size h (mm).
void writeTriangleScript(const std::string& name, double h) {
  std::ofstream(dir() / name) << fmt::format(R"(L = 20; W = 20; h = {};
Point(1) = {{0, -W/2, 0, h}}; Point(2) = {{L, -W/2, 0, h}}; Point(3) = {{L, W/2, 0, h}}; Point(4) = {{0, W/2, 0, h}};
Line(1) = {{1, 2}}; Line(2) = {{2, 3}}; Line(3) = {{3, 4}}; Line(4) = {{4, 1}};
Curve Loop(1) = {{1, 2, 3, 4}}; Plane Surface(1) = {{1}};
Physical Surface("gel") = {{1}};
)",
                                             h);
}

std::string scenarioText(const std::string& tissueLine, int nodes = 21, const std::string& extra = "") {
  return fmt::format(R"(name: imported
tissue:
  {}
  material: {{law: linear, E: 10 kPa, nu: 0.45}}
  friction: {{C_p: 3.791 N/m, b_p: 285.053 N s/m^2}}
  puncture: {{force: 0.05 N}}
  cutting: {{force: 0.04 N}}
needle: {{outer_diameter: 18 G, length: 100 mm, bevel_angle: 30 deg, tip: bevel}}
insertion:
  start_depth: -0.5 mm
  profile:
    - insert: {{to: 15 mm, speed: 10 mm/s}}
model:
  engine: realtime2d
  time_step: 1 ms
  realtime2d: {{nodes_depth: {}, nodes_lateral: {}, field_interval: 0 s{}}}
output: {{interval: 10 ms}}
)",
                     tissueLine, nodes, nodes, extra);
}

const std::string kBlock = "block: {length: 20 mm, width: 20 mm, height: 20 mm}";

Scenario read(const std::string& yaml) { return scenario::readText(yaml, (dir() / "scenario.yaml").string()); }

std::string refusal(const std::string& yaml) {
  try {
    const Scenario sc = read(yaml);
    engineFor(sc).preflight(sc);
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "expected an InputError";
  return "";
}

std::vector<double> column(const MemorySink& m, const std::string& name) { return m.tables.at("forces").column(name); }

double largestRelativeDifference(const std::vector<double>& a, const std::vector<double>& b) {
  EXPECT_EQ(a.size(), b.size());
  double largest = 0.0, scale = 0.0;
  for (double v : b) scale = std::max(scale, std::abs(v));
  for (std::size_t i = 0; i < std::min(a.size(), b.size()); ++i) largest = std::max(largest, std::abs(a[i] - b[i]));
  return largest / scale;
}

double mean(const std::vector<double>& v) { return std::accumulate(v.begin(), v.end(), 0.0) / static_cast<double>(v.size()); }
double relative(double a, double b) { return std::abs(a - b) / std::abs(b); }

// Collapsed quads (a, b, c, c) of triangles on the given nodes.
Mesh triangles(const Eigen::Matrix2Xd& nodes, const std::vector<Eigen::Vector3i>& tris) {
  Mesh m;
  m.nodes = nodes;
  m.triangles = true;
  m.quads.resize(4, static_cast<Eigen::Index>(tris.size()));
  for (std::size_t e = 0; e < tris.size(); ++e) m.quads.col(static_cast<Eigen::Index>(e)) << tris[e], tris[e][2];
  m.extent_x = nodes.row(0).maxCoeff();
  m.extent_y = nodes.row(1).maxCoeff();
  return m;
}

// Each test in a directory of its own, removed after it.
class Realtime2dImported : public ::testing::Test {
 protected:
  void TearDown() override { std::filesystem::remove_all(dir()); }
};

}  // namespace

TEST_F(Realtime2dImported, TheGeneratedBlockImportedGivesItsForcesInEveryUnit) {
  writeBlockScript("block_mm.geo", 1e-3);
  writeBlockScript("block_m.geo", 1.0);
  const auto generated = runInMemory(read(scenarioText(kBlock)));
  const auto mm = runInMemory(read(scenarioText("geometry: {file: block_mm.geo, unit: mm}")));
  const auto m = runInMemory(read(scenarioText("geometry: {file: block_m.geo, unit: m}")));
  const auto f = column(generated, "force_total");
  ASSERT_GT(*std::max_element(f.begin(), f.end()), 0.05);  // puncture, cutting and friction: about 0.1 N
  ASSERT_GT(std::abs(column(generated, "tip_deflection").back()), 1e-4);
  for (const char* c : {"force_total", "force_lateral", "tip_deflection", "force_friction", "coupled_nodes"}) {
    // the same nodes, elements, path and held sides: the same equations, round-off apart
    EXPECT_LT(largestRelativeDifference(column(mm, c), column(generated, c)), 1e-9) << c;
    EXPECT_LT(largestRelativeDifference(column(m, c), column(generated, c)), 1e-9) << c;
  }
  EXPECT_EQ(mm.results.at("puncture_depth").value, generated.results.at("puncture_depth").value);
}

// Unstructured triangles at 0.5 mm against the generated 0.5 mm grid (41 x 41 nodes): the
// mean and final axial force, the final lateral force and tip deflection agree within the
// generated grid's own change from 1 mm to 0.5 mm (its discretisation error at 1 mm, a bound
// for it at 0.5 mm). Measured: mean force 0.02 % apart (grid change 0.5 %), final force 0.8 %
// (1.3 %), tip deflection 0.03 % (0.13 %).
TEST_F(Realtime2dImported, UnstructuredTrianglesAgreeWithTheGeneratedGrid) {
  writeTriangleScript("tri_05.geo", 0.5);
  const auto coarse = runInMemory(read(scenarioText(kBlock, 21)));
  const auto fine = runInMemory(read(scenarioText(kBlock, 41)));
  const auto tri = runInMemory(read(scenarioText("geometry: {file: tri_05.geo, unit: mm}")));
  auto measures = [](const MemorySink& s) {
    return std::vector<double>{mean(column(s, "force_total")), column(s, "force_total").back(),
                               column(s, "force_lateral").back(), column(s, "tip_deflection").back()};
  };
  const auto c = measures(coarse), f = measures(fine), t = measures(tri);
  const char* names[] = {"mean force", "final force", "final lateral force", "final tip deflection"};
  for (std::size_t i = 0; i < c.size(); ++i) {
    const double own = std::max(relative(c[i], f[i]), 1e-3);  // at least 0.1 %
    EXPECT_LT(relative(t[i], f[i]), own) << names[i] << ": triangles " << t[i] << ", grid " << f[i] << ", 1 mm grid " << c[i];
  }
  EXPECT_EQ(tri.results.at("puncture_depth").value, fine.results.at("puncture_depth").value);
}

// The collapsed quad (a, b, c, c) has the rigid-body modes as zero-energy modes and, under a
// linear displacement field, the nodal forces of the constant-strain triangle (its 2 x 2 Gauss
// rule integrates adj(J) exactly).
TEST_F(Realtime2dImported, TheCollapsedQuadIsTheConstantStrainTriangleUnderLinearFields) {
  Eigen::Matrix<double, 2, 4> xy;
  xy << 0.0, 3e-3, 1e-3, 1e-3, 0.0, 0.5e-3, 2.5e-3, 2.5e-3;
  ElasticMaterial mat;
  const Eigen::Matrix3d D = elasticity(mat);
  const auto K = quadStiffness(xy, D, mat.thickness);
  Eigen::Matrix<double, 8, 1> tx, ty, rot, lin;
  for (int a = 0; a < 4; ++a) {
    tx.segment<2>(2 * a) << 1, 0;
    ty.segment<2>(2 * a) << 0, 1;
    rot.segment<2>(2 * a) << -xy(1, a), xy(0, a);
    lin.segment<2>(2 * a) << 0.01 * xy(0, a) + 0.004 * xy(1, a), -0.003 * xy(0, a) + 0.02 * xy(1, a);
  }
  const double scale = K.norm();
  EXPECT_LT((K * tx).norm(), 1e-12 * scale);
  EXPECT_LT((K * ty).norm(), 1e-12 * scale);
  EXPECT_LT((K * rot).norm(), 1e-12 * scale * 3e-3);
  // the constant-strain triangle: f = t A B^T D eps
  const Eigen::Vector3d eps(0.01, 0.02, 0.004 - 0.003);
  const double x1 = xy(0, 0), y1 = xy(1, 0), x2 = xy(0, 1), y2 = xy(1, 1), x3 = xy(0, 2), y3 = xy(1, 2);
  const double A2 = (x2 - x1) * (y3 - y1) - (x3 - x1) * (y2 - y1);
  const double b[3] = {y2 - y3, y3 - y1, y1 - y2}, c[3] = {x3 - x2, x1 - x3, x2 - x1};
  Eigen::Matrix<double, 3, 6> B = Eigen::Matrix<double, 3, 6>::Zero();
  for (int i = 0; i < 3; ++i) {
    B(0, 2 * i) = b[i] / A2;
    B(1, 2 * i + 1) = c[i] / A2;
    B(2, 2 * i) = c[i] / A2;
    B(2, 2 * i + 1) = b[i] / A2;
  }
  const Eigen::Matrix<double, 6, 1> fcst = B.transpose() * D * eps * (0.5 * A2 * mat.thickness);
  const Eigen::Matrix<double, 8, 1> fq = K * lin;
  Eigen::Matrix<double, 6, 1> fcollapsed = fq.head<6>();
  fcollapsed.tail<2>() += fq.tail<2>();  // the collapsed corner c carries both of its slots
  EXPECT_LT((fcollapsed - fcst).norm(), 1e-12 * fcst.norm()) << fcollapsed.transpose() << "\n" << fcst.transpose();
}

// Patch test on collapsed quads: a linear field imposed on the boundary of a fan of irregular
// triangles is reproduced at the inner node.
TEST_F(Realtime2dImported, CollapsedQuadsPassThePatchTest) {
  Eigen::Matrix2Xd x(2, 5);
  x << 0.0, 4e-3, 4.5e-3, -0.5e-3, 1.7e-3,  //
      0.0, 0.3e-3, 3.8e-3, 3.5e-3, 1.4e-3;
  const Mesh mesh = triangles(x, {{0, 1, 4}, {1, 2, 4}, {2, 3, 4}, {3, 0, 4}});
  const auto as = assemble(mesh, ElasticMaterial{}, false);
  auto exact = [](const Eigen::Vector2d& p) { return Eigen::Vector2d(1e-3 + 0.02 * p.x() - 0.01 * p.y(), 0.03 * p.x() + 0.015 * p.y()); };
  Eigen::VectorXd u = Eigen::VectorXd::Zero(10);
  for (int n = 0; n < 4; ++n) u.segment<2>(2 * n) = exact(mesh.nodes.col(n));
  // free DOFs 8, 9: K_ff u_f = -K_fp u_p
  const Eigen::MatrixXd K(as.K);
  const Eigen::Vector2d uf = K.block<2, 2>(8, 8).ldlt().solve(-K.block<2, 8>(8, 0) * u.head<8>());
  EXPECT_LT((uf - exact(mesh.nodes.col(4))).norm(), 1e-12 * exact(mesh.nodes.col(4)).norm());
  // the assembled mass is the triangles' area times rho t
  const double area = 0.5 * std::abs((x(0, 2) - x(0, 0)) * (x(1, 3) - x(1, 1)) - (x(0, 3) - x(0, 1)) * (x(1, 2) - x(1, 0)));
  const ElasticMaterial mat;
  EXPECT_NEAR(Eigen::VectorXd(as.M * Eigen::VectorXd::Ones(10)).sum() / 2.0, area * mat.density * mat.thickness,
              1e-12 * area * mat.density * mat.thickness);
}

TEST_F(Realtime2dImported, WhatItCannotTakeIsRefusedWithTheField) {
  writeBlockScript("block_mm.geo", 1e-3);
  const std::string geo = "geometry: {file: block_mm.geo, unit: mm}";
  std::string why = refusal(scenarioText(geo, 21, ", boundary: springs, spring_stiffness: 1e6 N/m^3"));
  EXPECT_NE(why.find("model.realtime2d.boundary"), std::string::npos) << why;
  why = refusal(scenarioText(geo, 21, ", markers: [{name: a, x: 5 mm, y: 2 mm}]"));
  EXPECT_NE(why.find("model.realtime2d.markers"), std::string::npos) << why;
  std::string layered = scenarioText(geo);
  layered.replace(layered.find("  material: {law"), layered.find("needle:") - layered.find("  material: {law"),
                  R"(  layers:
    - {name: gel, material: {law: linear, E: 10 kPa, nu: 0.45}, cutting: {force: 0.04 N}}
    - {name: more, material: {law: linear, E: 20 kPa, nu: 0.45}, cutting: {force: 0.04 N}}
)");
  why = refusal(layered);
  EXPECT_NE(why.find("tissue.layers"), std::string::npos) << why;
  // a 3D geometry: the engines that take one are named
  std::ofstream(dir() / "cube.geo") << R"(SetFactory("OpenCASCADE"); Box(1) = {0, -10, -10, 20, 20, 20};
Mesh.MeshSizeMax = 8; Physical Volume("gel") = {1};
)";
  why = refusal(scenarioText("geometry: {file: cube.geo, unit: mm}"));
  EXPECT_NE(why.find("engine realtime2d does not take an imported 3D geometry"), std::string::npos) << why;
  EXPECT_NE(why.find("explicit"), std::string::npos) << why;
  EXPECT_NE(why.find("mpm"), std::string::npos) << why;
}

// A disc of tissue (x from 2 to 22 mm): the entry membrane is where the axis meets its boundary
// (eq 3.16 from there to the puncture force), and the cutting stops where the axis leaves it.
TEST_F(Realtime2dImported, TheNeedleEntersAndLeavesWhereTheAxisCrossesTheMesh) {
  std::ofstream(dir() / "disc.geo") << R"(SetFactory("OpenCASCADE"); Disk(1) = {12, 0, 0, 10};
Mesh.MeshSizeMax = 0.7; Physical Surface("gel") = {1};
)";
  std::string yaml = scenarioText("geometry: {file: disc.geo, unit: mm}", 21, ", solver: reduced");
  yaml.replace(yaml.find("to: 15 mm"), 9, "to: 24 mm");
  const Scenario sc = read(yaml);
  const double entry = sc.tissue.geometry->entry_depth;
  EXPECT_NEAR(entry, 2e-3, 0.7e-3 * 0.7e-3 / (8 * 10e-3) + 1e-9);  // a chord of the circle
  const auto out = runInMemory(sc);
  const forces::StiffnessLaw law{10e3, 0.45, std::numbers::pi / 6, std::numbers::pi / 2};
  const double step = 10e-3 * 1e-3;  // 10 mm/s, 1 ms
  EXPECT_NEAR(out.results.at("puncture_depth").value, entry + law.depthAt(0.05) + 0.5 * step, 0.5 * step + 1e-9);
  const auto depth = column(out, "depth"), cut = column(out, "force_cutting");
  int inside = 0, beyond = 0;
  for (std::size_t i = 0; i < depth.size(); ++i) {
    if (depth[i] > 22.1e-3) {
      ++beyond;
      EXPECT_EQ(cut[i], 0.0) << depth[i];
    } else if (depth[i] > entry + law.depthAt(0.05) + step && depth[i] < 21.9e-3) {
      ++inside;
      EXPECT_NEAR(cut[i], 0.04, 1e-12) << depth[i];
    }
  }
  EXPECT_GT(inside, 50);
  EXPECT_GT(beyond, 5);
  for (double v : column(out, "force_total")) ASSERT_TRUE(std::isfinite(v));
}
