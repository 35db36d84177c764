// The shared insertion frame (needle/insertion_frame.hpp): right-handed, the
// documented tilt and bevel sides, and the bevel side matching the needle
// geometry's face normal (needle/surface_mesh.hpp).
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "needlesim/needle/insertion_frame.hpp"
#include "needlesim/needle/surface_mesh.hpp"

using namespace needlesim;
using Eigen::Vector3d;

namespace {
needle::InsertionFrame frameAt(double angleDeg, double bevelDeg = 0.0, double offset = 0.0) {
  InsertionSpec s;
  s.entry_angle = angleDeg * std::numbers::pi / 180.0;
  s.bevel_orientation = bevelDeg * std::numbers::pi / 180.0;
  s.entry_offset = offset;
  return needle::InsertionFrame::fromInsertion(s);
}
}  // namespace

TEST(InsertionFrame, NormalInsertionRunsAlongDepthWithLateralOnPlusY) {
  const auto f = frameAt(90.0, 0.0, 2e-3);
  EXPECT_EQ(f.axial, Vector3d::UnitX());  // exactly: no round-off of cos(90 deg)
  EXPECT_EQ(f.lateral, Vector3d::UnitY());
  EXPECT_NEAR((f.outOfPlane - Vector3d::UnitZ()).norm(), 0.0, 1e-15);
  EXPECT_NEAR((f.onAxis(0.01) - Vector3d(0.01, 2e-3, 0.0)).norm(), 0.0, 1e-15);
}

TEST(InsertionFrame, IsRightHandedAndOrthonormalAtEveryAngle) {
  for (double a : {10.0, 30.0, 45.0, 60.0, 90.0, 120.0}) {
    const auto f = frameAt(a);
    EXPECT_NEAR(f.axial.norm(), 1.0, 1e-14);
    EXPECT_NEAR(f.lateral.norm(), 1.0, 1e-14);
    EXPECT_NEAR(f.axial.dot(f.lateral), 0.0, 1e-14);
    EXPECT_NEAR((f.axial.cross(f.lateral) - f.outOfPlane).norm(), 0.0, 1e-14) << a;
    // the angle between the needle and the entry face (normal +x) is the entry angle
    EXPECT_NEAR(std::asin(f.axial.x()) * 180.0 / std::numbers::pi, a <= 90.0 ? a : 180.0 - a, 1e-9);
  }
}

TEST(InsertionFrame, ObliqueNeedleGoesTowardsPlusYAsItGoesDeeper) {
  const auto f = frameAt(60.0);
  const Vector3d tip = f.onAxis(0.02);
  EXPECT_GT(tip.x(), 0.0);
  EXPECT_NEAR(tip.y(), 0.02 * std::cos(60.0 * std::numbers::pi / 180.0), 1e-15);
}

TEST(InsertionFrame, BevelSideTurnsWithTheOrientationAndRoll) {
  const auto f = frameAt(90.0, 0.0);
  EXPECT_NEAR((f.bevelSide() - Vector3d::UnitY()).norm(), 0.0, 1e-15);
  EXPECT_NEAR((f.bevelSide(std::numbers::pi / 2) - Vector3d::UnitZ()).norm(), 0.0, 1e-15);
  EXPECT_NEAR((frameAt(90.0, 180.0).bevelSide() + Vector3d::UnitY()).norm(), 0.0, 1e-15);
  EXPECT_EQ(f.bevelSign(), 1.0);
  EXPECT_EQ(frameAt(90.0, 180.0).bevelSign(), -1.0);
  EXPECT_EQ(f.bevelSign(std::numbers::pi), -1.0);
}

// The bevel face of the shared needle geometry looks to +bevelSide: its outward
// normal has a positive bevelSide part, so the tissue's pressure on it pushes the
// tip towards -bevelSide (-lateral at orientation 0).
TEST(InsertionFrame, BevelFaceOfTheNeedleGeometryLooksToTheBevelSide) {
  const auto f = frameAt(70.0, 0.0);
  needle::NeedleShape shape;
  shape.radius = 0.5e-3;
  shape.length = 0.1;
  shape.tipAngle = 30.0 * std::numbers::pi / 180.0;
  shape.tip = TipType::Bevel;
  needle::NeedlePose pose;
  pose.axis = f.axial;
  pose.bevelSide = f.bevelSide();
  pose.tip = f.onAxis(0.01);  // the axis point level with the sharp point (at -R bevelSide)
  // a point just inside the bevel face, behind the tip, on the heel side of the axis:
  // margin to the face R cos(a) + a_lat cos(a) - |s| sin(a) = 0.057 mm < 0.2 mm to the wall
  const Vector3d p = f.onAxis(0.01) - 1.5e-3 * f.axial + 0.3e-3 * f.lateral;
  const auto hit = needle::queryNeedle(shape, pose, p, false);
  ASSERT_TRUE(hit.inside);
  ASSERT_EQ(hit.face, needle::NeedleFace::Tip);
  EXPECT_GT(hit.normal.dot(f.lateral), 0.0);
  EXPECT_GT(hit.normal.dot(f.axial), 0.0);
}
