// realtime3d's path that follows the tip (model.realtime3d.path: follow_tip): the bevel needle's tip
// leaves the entry axis on the kinematic bevel-tip arc (Webster et al. 2006, seed 002 section 1),
// moved by the tissue it deforms; a symmetric tip, or a bevel turned every few mm, stays on the axis.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>

#include "needlesim/engines/memory_sink.hpp"
#include "needlesim/engines/realtime3d/session.hpp"
#include "needlesim/scenario/reader.hpp"

using namespace needlesim;
using namespace needlesim::realtime3d;

namespace {

constexpr double kKappa = 4.1667;  // 1/m, seed 002 Table 2, gel C with the 0.54 mm needle (1 / 240 mm)
constexpr double kDepth = 0.06;    // m inserted

// Seed 002's gel C block and 0.54 mm Nitinol needle (examples/planning/gel_block.yaml), coarse.
std::string gelBlock(const std::string& tip, const std::string& profile) {
  return R"(
name: follow_tip
tissue:
  block: {length: 80 mm, width: 50 mm, height: 50 mm}
  material: {law: neo-hookean, C10: 7.55 kPa, nu: 0.45}
  cutting: {force: 0.02 N}
  friction: {coefficient: 0.3}
needle: {outer_diameter: 0.54 mm, inner_diameter: 0 mm, length: 150 mm, bevel_angle: 34.85 deg, tip: )" + tip + R"(,
         youngs_modulus: 50 GPa}
insertion:
  profile:
)" + profile + R"(
model:
  engine: realtime3d
  time_step: 2 ms
  realtime3d: {nodes_depth: 17, nodes_lateral: 9, nodes_height: 9, refinement: 4, coupling_spacing: 2 mm,
               field_interval: 0 s, path: follow_tip, curvature: 4.1667 1/m}
output: {interval: 20 ms}
)";
}

const std::string kStraightIn = "    - insert: {to: 60 mm, speed: 10 mm/s}";

struct TipEnd {
  double axial = 0.0, off = 0.0;  // m: along the entry axis from the entry, off it
};

TipEnd tipEnd(const MemorySink& m) {
  const io::Table& t = m.tables.at("forces");
  const std::size_t last = t.rows() - 1;
  auto at = [&](std::size_t r, const char* c) { return t.at(r, t.columnIndex(c)); };
  // the first row: the tip on the entry face, on the axis (x along the axis, y and z across it)
  const double x0 = at(0, "tip_x"), y0 = at(0, "tip_y"), z0 = at(0, "tip_z");
  return {at(last, "tip_x") - x0, std::hypot(at(last, "tip_y") - y0, at(last, "tip_z") - z0)};
}

// The tissue's lateral give at the tip (Hetenyi's semi-infinite beam on a Winkler foundation under
// its end moment M = EI kappa: w = 2 M lambda^2 / K_T, lambda = (K_T / 4 EI)^(1/4)), with gel C's
// K_T = 12.61 kN/m^2 (seed 002 section 3.1) and EI of the 0.54 mm Nitinol needle: the most the
// channel's end can be moved across by the needle bent in it.
double tissueGive() {
  const double EI = 50e9 * std::numbers::pi / 64.0 * std::pow(0.54e-3, 4), K_T = 12.61e3;
  const double lambda = std::pow(K_T / (4.0 * EI), 0.25);
  return 2.0 * EI * kKappa * lambda * lambda / K_T;
}

}  // namespace

// The tip's path is the arc of curvature kappa tangent to the entry axis, moved by the tissue's
// give w at the tip: the circle through the entry and the tip, tangent there, has curvature
// 2 y / (x^2 + y^2), within 2 w / x^2 of kappa (7 % here). On the straight path it stays on the axis.
TEST(Realtime3dFollowTip, BevelTipLeavesTheAxisOnTheKinematicArc) {
  const MemorySink m = runInMemory(scenario::readText(gelBlock("bevel", kStraightIn), "<gel block>"));
  const TipEnd e = tipEnd(m);
  const double kappa = 2.0 * e.off / (e.axial * e.axial + e.off * e.off);
  const double tol = 2.0 * tissueGive() / (e.axial * e.axial);
  std::printf("axial %.2f mm, off the axis %.3f mm: curvature %.4f 1/m (kinematic %.4f +- %.4f)\n", e.axial * 1e3,
              e.off * 1e3, kappa, kKappa, tol);
  EXPECT_GT(e.axial, 0.9 * kDepth);
  EXPECT_NEAR(kappa, kKappa, tol);
}

// A conical tip has no bevel to steer it: the channel runs straight on. A bevel turned by 180 deg
// every l = 5 mm (the first turn after l/2) zigzags about the axis by at most kappa l^2 / 8;
// either stays within that plus the tissue's give of the axis, while the fixed bevel leaves it
// by kappa D^2 / 2 (7.5 mm).
TEST(Realtime3dFollowTip, SymmetricTipOrAlternatingBevelStaysOnTheAxis) {
  const double l = 5e-3, bound = kKappa * l * l / 8.0 + tissueGive();
  const TipEnd cone = tipEnd(runInMemory(scenario::readText(gelBlock("conical", kStraightIn), "<cone>")));
  std::string flips = "    - insert: {to: 2.5 mm, speed: 10 mm/s}\n";
  for (int k = 1; k < 12; ++k)
    flips += "    - rotate: {by: 180 deg, rate: 3600 deg/s, axis: axial}\n    - insert: {to: " + std::to_string(2.5 + 5 * k) +
             " mm, speed: 10 mm/s}\n";
  flips += "    - rotate: {by: 180 deg, rate: 3600 deg/s, axis: axial}\n    - insert: {to: 60 mm, speed: 10 mm/s}";
  const TipEnd spun = tipEnd(runInMemory(scenario::readText(gelBlock("bevel", flips), "<alternating bevel>")));
  std::printf("cone: %.4f mm off the axis, alternating bevel: %.4f mm (bound %.4f mm)\n", cone.off * 1e3,
              spun.off * 1e3, bound * 1e3);
  EXPECT_GT(cone.axial, 0.9 * kDepth);
  EXPECT_LT(cone.off, bound);
  EXPECT_LT(spun.off, bound);
}

// A path point moved onto other tets takes the path flexibility of a point embedded there from the
// start: its own block of S (which depends on its embedding alone) equals that of a tissue whose
// axis runs through the new place, on every back-end (the same mesh: its refined line is fixed).
TEST(Realtime3dFollowTip, AMovedPathPointHasTheFlexibilityOfOneEmbeddedThere) {
  for (const Backend b : {Backend::Direct, Backend::Modal, Backend::Reduced}) {
    TissueConfig c = gelatinBlockConfig(9, 7, b).tissue;
    c.block.length = c.block.width = c.block.height = 0.03;
    c.block.path_y = c.block.path_z = 0.015;
    c.coupling_spacing = 2e-3;
    c.coupling_radius = 0.3e-3;
    const Eigen::Vector3d t = Eigen::Vector3d::UnitX(), n = Eigen::Vector3d::UnitY();
    const Eigen::Vector3d on(0.0, 0.015, 0.015), off(0.0, 0.0163, 0.0141);  // off: between the grid lines
    Tissue moved(c, on, t, n, 1e-3, 0.0, 0.02);
    const Tissue there(c, off, t, n, 1e-3, 0.0, 0.02);
    const int i = 4;
    ASSERT_TRUE(moved.movePathPoint(i, off + moved.path()[i].s * t, t));
    const Eigen::Matrix3d a = moved.dynamics().pathCompliance().block<3, 3>(3 * i, 3 * i);
    const Eigen::Matrix3d e = there.dynamics().pathCompliance().block<3, 3>(3 * i, 3 * i);
    const Eigen::Matrix3d was = Tissue(c, on, t, n, 1e-3, 0.0, 0.02).dynamics().pathCompliance().block<3, 3>(3 * i, 3 * i);
    EXPECT_NEAR((a - e).norm(), 0.0, 1e-9 * e.norm()) << static_cast<int>(b);
    EXPECT_GT((was - e).norm(), 1e-3 * e.norm()) << static_cast<int>(b);  // the move matters
  }
}
