// The mpm engine in the shared insertion frame (needle/insertion_frame.hpp):
// the bevel's lateral force and the oblique needle's tip follow the frame's
// conventions, and the rigid needle's geometry agrees with needle::queryNeedle.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <random>

#include "mpm_test_scenario.hpp"
#include "needlesim/engines/mpm/mpm_solver.hpp"
#include "needlesim/needle/surface_mesh.hpp"

using namespace needlesim;
using namespace needlesim::mpm_test;

namespace {

// The small block with a 1 mm bevel needle (30 deg) turned to `orientation`, 3 mm deep, in the grid
// contact: its needle is analytic, so the mirror images agree to round-off (the default CFEMP
// contact's cut through the axis turns the lateral force towards the bevel side,
// docs/validation/agreement.md "Open").
std::string bevelScenario(const std::string& orientation, const std::string& extraInsertion = "") {
  std::string s = replaced(smallScenario("    contact: grid\n", "bevel"), "length: 40 mm", "length: 40 mm\n  bevel_angle: 30 deg");
  return replaced(s, "start_depth: -0.5 mm", "start_depth: -0.5 mm\n  bevel_orientation: " + orientation +
                                                  extraInsertion);
}

// Mean of a forces.csv column over the rows deeper than 1 mm.
double meanBelow1mm(const MemorySink& out, const std::string& column) {
  const io::Table& f = out.tables.at("forces");
  const auto depth = f.column("depth"), v = f.column(column);
  double sum = 0.0;
  int n = 0;
  for (std::size_t i = 0; i < f.rows(); ++i)
    if (depth[i] > 1e-3) {
      sum += v[i];
      ++n;
    }
  return sum / n;
}

}  // namespace

// The tissue's pressure on the bevel face pushes the tip towards -bevelSide
// (seed 002 section 3, seed 003 section 3.4): at bevel_orientation 0 the
// bevel looks to +lateral, so force_lateral < 0; turned by 180 deg it looks to
// -lateral and the sign flips; the two are mirror images in the symmetric
// block, so their magnitudes agree to the lattice's asymmetry.
TEST(MpmFrame, BevelLateralForceSign) {
  const MemorySink at0 = runText(bevelScenario("0 deg"));
  const MemorySink at180 = runText(bevelScenario("180 deg"));
  const double f0 = meanBelow1mm(at0, "force_lateral"), f180 = meanBelow1mm(at180, "force_lateral");
  const double axial = meanBelow1mm(at0, "force_total");
  std::printf("bevel 0 deg: lateral %.4g N, 180 deg: %.4g N (axial %.4g N)\n", f0, f180, axial);
  EXPECT_GT(axial, 0.0);
  EXPECT_LT(f0, 0.0);
  EXPECT_GT(f180, 0.0);
  EXPECT_NEAR(f0, -f180, 1e-3 * std::abs(f0));  // mirror images: equal up to round-off
}

// An oblique needle (entry_angle 60 deg) goes towards +y as it goes deeper:
// the tip row follows the frame's axis from the entry point.
TEST(MpmFrame, ObliqueTipMovesTowardsPlusY) {
  std::string s = replaced(smallScenario("", "conical"), "start_depth: -0.5 mm",
                           "start_depth: -0.5 mm\n  entry_angle: 60 deg\n  entry_offset: -1 mm");
  s = replaced(s, "to: 3 mm", "to: 2 mm");
  const MemorySink out = runText(s);
  const io::Table& f = out.tables.at("forces");
  const double depth = f.column("depth").back();
  const double th = std::numbers::pi / 3;
  EXPECT_NEAR(f.column("tip_x").back(), depth * std::sin(th), 1e-12);
  EXPECT_NEAR(f.column("tip_y").back(), -1e-3 + depth * std::cos(th), 1e-12);
  EXPECT_GT(f.column("tip_y").back(), -1e-3);
  EXPECT_NEAR(f.column("tip_z").back(), 0.0, 1e-12);
  EXPECT_GT(out.results.at("final_force").value, 0.0);
}

// The rigid needle's signed distance (RigidBody::distance, the grid contact's
// geometry) and the shared needle geometry (needle::queryNeedle) describe the
// same solid: at random points around a bevel, a conical and a blunt tip,
// inside for one is inside for the other, with the same depth, the same face
// (tip or wall) and the same outward normal.
TEST(MpmFrame, RigidNeedleAgreesWithSharedNeedleGeometry) {
  using mpm::RigidBody;
  using mpm::Vec3;
  const double R = 0.5e-3;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const Vec3 axis = Vec3(0.5, std::sqrt(3.0) / 2, 0.0), side = Vec3(-std::sqrt(3.0) / 2, 0.5, 0.0).normalized();
  const Vec3 bevelSide = std::cos(0.4) * side + std::sin(0.4) * Vec3::UnitZ();
  for (const RigidBody::Tip tip : {RigidBody::Tip::Bevel, RigidBody::Tip::Conical, RigidBody::Tip::Blunt}) {
    RigidBody rb;
    rb.kind = RigidBody::Kind::Needle;
    rb.tip = tip;
    rb.radius = R;
    rb.tipAngle = tip == RigidBody::Tip::Blunt ? 0.5 * std::numbers::pi : 0.35;
    rb.axis = axis;
    rb.bevelSide = bevelSide;
    rb.point = Vec3(1e-3, 2e-3, -1e-3);  // the foremost point (a bevel's sharp point)
    needle::NeedleShape shape;
    shape.radius = R;
    shape.length = 40e-3;
    shape.tipAngle = rb.tipAngle;
    shape.tip = tip == RigidBody::Tip::Bevel ? TipType::Bevel : tip == RigidBody::Tip::Conical ? TipType::Conical
                                                                                              : TipType::Blunt;
    // The shared pose's tip is the axis point level with the foremost point
    // (a bevel's sharp point lies at -R bevelSide from it).
    const Vec3 level = tip == RigidBody::Tip::Bevel ? Vec3(rb.point + R * bevelSide) : rb.point;
    const needle::NeedlePose pose{level, axis, bevelSide};
    const Vec3 ortho = axis.cross(bevelSide);
    int inside = 0, outside = 0;
    for (int i = 0; i < 4000; ++i) {
      // Around the tip: from 4R behind the foremost point to R ahead of it, radius up to 1.5 R.
      const Vec3 x = rb.point + (-1.5 * R + 2.5 * R * u(rng)) * axis + 1.5 * R * u(rng) * bevelSide +
                     1.5 * R * u(rng) * ortho;
      Vec3 n;
      int part = -1;
      const double d = rb.distance(x, &n, &part);
      const needle::NeedleHit hit = needle::queryNeedle(shape, pose, x, false);
      if (std::abs(d) < 1e-12) continue;  // on the surface
      if (d > 0) {
        ++outside;
        EXPECT_FALSE(hit.inside) << "point " << i << " outside by " << d;
        continue;
      }
      ++inside;
      ASSERT_TRUE(hit.inside) << "point " << i << " inside by " << -d;
      EXPECT_NEAR(hit.depth, -d, 1e-12);
      EXPECT_EQ(hit.face == needle::NeedleFace::Tip, part == 1);
      EXPECT_LT((hit.normal - n).norm(), 1e-9);
    }
    EXPECT_GT(inside, 200);
    EXPECT_GT(outside, 200);
  }
}
