// Tissue markers of the explicit engine (model.explicit.markers, docs/models/explicit.md "Markers"):
// located in the element holding the reference point, interpolated by its shape functions, written
// with the real-time engines' columns; and the drag of a marker beside the path against realtime3d
// when realtime3d is given the loads explicit 3D produced (docs/validation/agreement.md).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include "needlesim/core/error.hpp"
#include "needlesim/engines/explicit/marker_location.hpp"
#include "needlesim/engines/memory_sink.hpp"
#include "needlesim/scenario/reader.hpp"

using namespace needlesim;
using explicit_fe::ElementType;
using explicit_fe::Mesh;

namespace {

// A marker's weights reproduce every linear field: sum w_a = 1 and sum w_a X_a = X (the shape functions'
// partition of unity and linear completeness), on graded grids of each element type.
void expectLinearReproduction(const Mesh& m, const Eigen::Vector3d& X) {
  const auto p = explicit_fe::locateMarker(m, X);
  ASSERT_TRUE(p.has_value()) << X.transpose();
  double sum = 0.0;
  Eigen::Vector3d Y = Eigen::Vector3d::Zero();
  for (std::size_t a = 0; a < p->nodes.size(); ++a) {
    sum += p->weights[a];
    for (int i = 0; i < m.dim; ++i) Y[i] += p->weights[a] * m.coord(p->nodes[a], i);
    EXPECT_GE(p->weights[a], -1e-9);
  }
  EXPECT_NEAR(sum, 1.0, 1e-12);
  for (int i = 0; i < m.dim; ++i) EXPECT_NEAR(Y[i], X[i], 1e-12) << "component " << i;
}

const std::vector<double> kXs{0.0, 0.3, 0.7, 1.4, 2.5}, kYs{-1.0, -0.2, 0.5, 1.1}, kZs{-0.8, 0.1, 0.9};

}  // namespace

TEST(ExplicitMarkers, TheLocatedPointReproducesLinearFieldsInEveryElement) {
  const Eigen::Vector3d inside(1.9, 0.13, 0.42), onAFace(0.7, -0.2, 0.1);
  for (ElementType t : {ElementType::Quad4, ElementType::Tri3}) {
    const Mesh m = explicit_fe::structuredBlock(kXs, kYs, t);
    expectLinearReproduction(m, inside);
    expectLinearReproduction(m, onAFace);
    EXPECT_FALSE(explicit_fe::locateMarker(m, Eigen::Vector3d(2.6, 0.0, 0.0)).has_value());
  }
  for (ElementType t : {ElementType::Hex8, ElementType::Tet4}) {
    Mesh m = explicit_fe::structuredBlock(kXs, kYs, kZs, t);
    expectLinearReproduction(m, inside);
    expectLinearReproduction(m, onAFace);
    EXPECT_FALSE(explicit_fe::locateMarker(m, Eigen::Vector3d(1.0, 0.0, 1.0)).has_value());
  }
  // a distorted hexahedron (an imported mesh's): the Newton inverse of the trilinear map
  Mesh m = explicit_fe::structuredBlock({0.0, 1.0}, {0.0, 1.0}, {0.0, 1.0}, ElementType::Hex8);
  m.X[3 * 6 + 0] = 1.4, m.X[3 * 6 + 1] = 1.3, m.X[3 * 6 + 2] = 1.2;  // the corner (1, 1, 1) pulled out
  expectLinearReproduction(m, Eigen::Vector3d(0.9, 0.8, 0.85));
}

namespace {

// The reference gel and needle (examples/agreement/reference.yaml) in a small block, the marker 2 mm beside
// the path and 4 mm behind the final tip. engine: explicit (3D, 0.6 mm core: 3 elements across the slit) or
// realtime3d (given `loads`: the tissue's cutting and friction lines, and its tip_load_ratio). The CI block
// (10 x 8 x 8 mm, 6.5 mm in) or the long one (14 x 10 x 10 mm, 8 mm in: the reduced reference's marker).
struct DragBlock {
  std::string block, to, markerX, rtNodes;
};
const DragBlock kSmall{"{length: 10 mm, width: 8 mm, height: 8 mm}", "6.5 mm", "2.5 mm",
                       "nodes_depth: 21, nodes_lateral: 17, nodes_height: 17"};
const DragBlock kLong{"{length: 14 mm, width: 10 mm, height: 10 mm}", "8 mm", "4 mm",
                      "nodes_depth: 29, nodes_lateral: 21, nodes_height: 21"};

std::string dragYaml(const DragBlock& b, const std::string& engine, const std::string& loads = "",
                     const std::string& rtExtra = "") {
  const std::string marker = "[{name: beside_path, x: " + b.markerX + ", y: 2 mm, z: 0 mm}]";
  return R"(
name: marker_drag
tissue:
  block: )" + b.block + R"(
  material: {law: neo-hookean, C10: 3.5 kPa, nu: 0.45, density: 1000 kg/m^3}
)" + loads + R"(
needle: {outer_diameter: 1.27 mm, length: 30 mm, bevel_angle: 30 deg, tip: bevel, youngs_modulus: 200 GPa}
insertion:
  entry_angle: 90 deg
  start_depth: -0.5 mm
  profile:
    - insert: {to: )" + b.to + R"(, speed: 10 mm/s}
model:
  engine: )" + engine + R"(
  time_step: 1 ms
  explicit: {dimension: 3d, element: hex8, element_size: 0.6 mm, max_element_size: 1.5 mm, core_width: 3 mm,
             mass_scaling: 100, tip_friction: 0, markers: )" + marker + R"(}
  realtime3d: {)" + b.rtNodes + R"(, refinement: 2, boundary: far-face, field_interval: 0 s,
               )" + rtExtra + R"(markers: )" + marker + R"(}
output: {interval: 20 ms}
)";
}

// The explicit run on a block, once per test program (two tests read it).
const MemorySink& explicitDrag(const DragBlock& b) {
  static std::map<std::string, MemorySink> runs;
  auto it = runs.find(b.block);
  if (it == runs.end())
    it = runs.emplace(b.block, runInMemory(scenario::readText(dragYaml(b, "explicit", "  friction: {coefficient: 0.25}\n"),
                                                                "<drag explicit>")))
             .first;
  return it->second;
}

}  // namespace

// The marker's columns and results are the real-time engines' (markers.csv: time, <name>_ux, _uy, _uz);
// the shaft drags the tissue beside it deeper (u_x > 0) and the slit opened into the needle pushes it
// aside (u_y > 0 on the +y side).
TEST(ExplicitMarkers, AMarkerBesideThePathIsDraggedDeeperAndPushedAside) {
  const MemorySink& r = explicitDrag(kSmall);
  const io::Table& t = r.tables.at("markers");
  std::vector<std::string> names;
  for (const auto& c : t.columns()) names.push_back(c.name);
  EXPECT_EQ(names, (std::vector<std::string>{"time", "beside_path_ux", "beside_path_uy", "beside_path_uz"}));
  EXPECT_EQ(t.column("time").size(), r.tables.at("forces").column("time").size());
  const double ux = r.results.at("marker_beside_path_ux_final").value, uy = r.results.at("marker_beside_path_uy_final").value;
  std::printf("marker at (2.5, 2, 0) mm with the tip at 6.5 mm: u_x %.4f mm, u_y %.4f mm\n", ux * 1e3, uy * 1e3);
  EXPECT_GT(ux, 0.0);
  EXPECT_GT(uy, 0.0);
  EXPECT_GE(r.results.at("marker_beside_path_ux_max").value, ux);
}

// A marker outside the block is refused with the field, as in the real-time engines.
TEST(ExplicitMarkers, AMarkerOutsideTheBlockIsRefused) {
  std::string text = dragYaml(kSmall, "explicit", "  friction: {coefficient: 0.25}\n");
  const std::string at = "x: 2.5 mm, y: 2 mm";
  text.replace(text.find(at), at.size(), "x: 2.5 mm, y: 5 mm");
  try {
    scenario::readText(text, "<outside>");
    ADD_FAILURE() << "accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("lies outside the tissue block"), std::string::npos) << e.what();
  }
}

namespace {

// Least-squares slope of y against x over the rows with x >= from.
double slopeFrom(const std::vector<double>& x, const std::vector<double>& y, double from) {
  double n = 0, sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (std::size_t i = 0; i < x.size(); ++i)
    if (x[i] >= from) n += 1, sx += x[i], sy += y[i], sxx += x[i] * x[i], sxy += x[i] * y[i];
  return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}

double meanFrom(const std::vector<double>& x, const std::vector<double>& y, double from) {
  double n = 0, s = 0;
  for (std::size_t i = 0; i < x.size(); ++i)
    if (x[i] >= from) n += 1, s += y[i];
  return s / n;
}

// The loads explicit 3D produced, as realtime3d's inputs: friction per length C_p = the slope of force_shaft
// against depth (the wall's friction grows by C_p per length inserted), the cutting force = force_tip and the
// bevel's transverse load per unit cutting force = -force_tip_lateral / force_tip, over the second half.
struct MatchedLoads {
  double Cp = 0, cutting = 0, ratio = 0;
};

MatchedLoads loadsOf(const MemorySink& r) {
  const io::Table& f = r.tables.at("forces");
  const auto d = f.column("depth");
  const double half = 0.5 * d.back();
  MatchedLoads m;
  m.Cp = slopeFrom(d, f.column("force_shaft"), half);
  m.cutting = meanFrom(d, f.column("force_tip"), half);
  m.ratio = -meanFrom(d, f.column("force_tip_lateral"), half) / m.cutting;
  return m;
}


// realtime3d vs explicit 3D on the drag of a marker beside the path, with matched loads (realtime3d given the
// friction per length, cutting force and bevel load explicit produced). Tolerance TOL, derived:
//  - load distribution: explicit's friction acts on the two lips within the needle's radius R = 0.635 mm,
//    realtime3d's on the path line. Outside the loaded circle an anti-plane load's axisymmetric part gives the
//    line load's field exactly; the rest decays as (R/r)^m for its mode cos(m theta): at r = 2 mm (R/r)^2 =
//    10 % for m = 2; the load is symmetric about the plane normal to the slit, and about the slit's plane to
//    within the lateral force's share of the wall's normal load (|force_lateral| / (force_shaft / mu), 6-8 %
//    on the reference at 10-20 mm), whose m = 1 part decays as R/r = 32 %: 3 %, within the 10 %.
//  - large deformation: the drag is anti-plane shear, linear in the shear strain for neo-Hooke (simple
//    shear's stress is mu gamma exactly); gamma = C_p / (2 pi mu r) ~ 0.1 at the marker. The opening of the
//    slit moves the marker out by ~ R^2 / (2 r) = 0.1 mm, changing ln(r) by 5 %.
//  - meshes: realtime3d's tets (0.25-0.33 mm on the path, twice that at the block's sides) and explicit's
//    0.6 mm core resolve the log profile of the drag between path and marker with three to six elements:
//    ~10 % each.
// TOL = 0.10 + 0.05 + 0.10 + 0.10 = 35 % of explicit's u_x. The marker lies 4 mm behind the tip, past the
// bevel (2R / tan 30 deg = 2.2 mm) whose frictionless faces carry no drag in explicit while realtime3d's C_p
// acts up to the tip: beside the heel (the tip 5 mm in, the marker 2.5 mm) realtime3d drags it 31 % further.
// Measured 4 mm behind the tip: -0.7 % (CI block), +1.1 % (long block, with a slit through the axis).
void expectMatchedDrag(const DragBlock& b) {
  const MemorySink& ex = explicitDrag(b);
  const MatchedLoads m = loadsOf(ex);
  const std::string loads = "  cutting: {force: " + std::to_string(m.cutting * 1e3) + " mN}\n  friction: {C_p: " +
                            std::to_string(m.Cp) + " N/m}\n";
  const MemorySink rt = runInMemory(scenario::readText(
      dragYaml(b, "realtime3d", loads, "tip_load_ratio: " + std::to_string(std::max(m.ratio, 0.0)) + ", "),
      "<drag realtime3d>"));
  const double uxE = ex.results.at("marker_beside_path_ux_final").value;
  const double uxR = rt.results.at("marker_beside_path_ux_final").value;
  std::printf("explicit loads: C_p %.3f N/m, cutting %.2f mN, bevel ratio %.2f; marker u_x explicit %.4f mm, "
              "realtime3d %.4f mm (%+.1f %%); u_y %.4f / %.4f mm\n",
              m.Cp, m.cutting * 1e3, m.ratio, uxE * 1e3, uxR * 1e3, 100 * (uxR / uxE - 1),
              ex.results.at("marker_beside_path_uy_final").value * 1e3,
              rt.results.at("marker_beside_path_uy_final").value * 1e3);
  ASSERT_GT(m.Cp, 0.0);
  ASSERT_GT(uxE, 0.0);
  EXPECT_NEAR(uxR, uxE, 0.35 * uxE);
}

}  // namespace

TEST(ExplicitMarkers, DragMatchesRealtime3dUnderTheLoadsExplicitProduced) { expectMatchedDrag(kSmall); }

// The same on a longer insertion (8 mm, the marker 4 mm deep: the reduced reference's marker).
TEST(ExplicitMarkers, LongDragMatchesRealtime3dUnderTheLoadsExplicitProduced) { expectMatchedDrag(kLong); }
