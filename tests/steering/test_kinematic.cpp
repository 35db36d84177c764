// Kinematic nonholonomic bevel-tip model (Webster et al. 2006) in 3D.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "needlesim/engines/steering/curvature_fit.hpp"
#include "needlesim/engines/steering/kinematic.hpp"

using namespace needlesim::steering;
constexpr double pi = std::numbers::pi;

TEST(Kinematic, ConstantBevelTracesACircleOfRadiusOneOverKappa) {
  const double kappa = 1 / 0.3;  // 300 mm radius
  KinematicParams par{kappa, 1e-3};
  const Control plan[] = {{0, 0.15}};
  std::vector<Vec3> pts(kinematicSampleCount(par, plan));
  Pose end;
  const int n = simulateKinematic(par, Pose{}, plan, pts, &end);
  ASSERT_EQ(n, 151);
  // exact: every point at distance 1/kappa from the centre (0, -1/kappa, 0), in the y-z plane
  const Vec3 c(0, -1 / kappa, 0);
  for (const Vec3& p : pts) {
    EXPECT_NEAR((p - c).norm(), 1 / kappa, 1e-12);
    EXPECT_NEAR(p.x(), 0.0, 1e-15);
  }
  // tip after arc s: (0, -(1 - cos ks)/k, sin(ks)/k); curving towards -y (bevel direction)
  const double s = 0.15;
  EXPECT_NEAR(end.p.y(), -(1 - std::cos(kappa * s)) / kappa, 1e-12);
  EXPECT_NEAR(end.p.z(), std::sin(kappa * s) / kappa, 1e-12);
  EXPECT_NEAR((end.R.transpose() * end.R - Mat3::Identity()).norm(), 0, 1e-12);
  EXPECT_NEAR(fitCircle(pts).radius, 0.3, 1e-9);
}

TEST(Kinematic, RotatedBevelTurnsThePlane) {
  // rotating the bevel by 90 deg about the axis makes the needle curve towards +x
  KinematicParams par{5.0, 1e-3};
  const Control plan[] = {{pi / 2, 0.1}};
  std::vector<Vec3> pts(kinematicSampleCount(par, plan));
  Pose end;
  simulateKinematic(par, Pose{}, plan, pts, &end);
  EXPECT_NEAR(end.p.x(), (1 - std::cos(0.5)) / 5.0, 1e-12);
  EXPECT_NEAR(end.p.y(), 0.0, 1e-14);
}

TEST(Kinematic, HalfwayFlipGivesTheSCurve) {
  // Flip 180 deg at s = L/2: two arcs of radius r, centres on opposite sides; the tip leaves
  // parallel to the start axis with lateral offset 2 r (1 - cos(L/2r)) and axial
  // advance 2 r sin(L/2r).
  const double kappa = 1 / 0.25, L = 0.15, r = 1 / kappa;
  KinematicParams par{kappa, 0.5e-3};
  const Control plan[] = {{0, L / 2}, {pi, L / 2}};
  std::vector<Vec3> pts(kinematicSampleCount(par, plan));
  Pose end;
  simulateKinematic(par, Pose{}, plan, pts, &end);
  const double th = L / (2 * r);
  EXPECT_NEAR(end.p.y(), -2 * r * (1 - std::cos(th)), 1e-12);
  EXPECT_NEAR(end.p.z(), 2 * r * std::sin(th), 1e-12);
  EXPECT_NEAR(end.R.col(2).dot(Vec3::UnitZ()), 1.0, 1e-12);  // tangent parallel to the start
  // inflection halfway: each half is a circle of radius r
  const int half = static_cast<int>(pts.size()) / 2;
  EXPECT_NEAR(fitCircle(std::span<const Vec3>(pts).first(half)).radius, r, 1e-9);
  EXPECT_NEAR(fitCircle(std::span<const Vec3>(pts).last(half)).radius, r, 1e-9);
  // a single circle fits the whole S-curve badly
  EXPECT_GT(fitCircle(pts).rms, 1e-4);
}

TEST(Kinematic, DutyCyclingGivesTheCommandedCurvature) {
  // Minhas et al. 2007: kappa_eff = kappa (1 - DC). The tolerance covers the helical
  // spin phase (one turn per 2 mm cycle): a deviation of order (kappa * cycle)^2.
  const double kappa = 1 / 0.2;
  for (double kcmd : {0.0, 1.0, 2.5, 4.0}) {
    const double dc = dutyCycleFor(kappa, kcmd);
    EXPECT_NEAR(dutyCycleCurvature(kappa, dc), kcmd, 1e-12);
    KinematicParams par{kappa, 0.25e-3};
    Control c;
    c.length = 0.15;
    c.duty_cycle = dc;
    c.cycle_length = 2e-3;
    const Control plan[] = {c};
    std::vector<Vec3> pts(kinematicSampleCount(par, plan));
    simulateKinematic(par, Pose{}, plan, pts);
    const CircleFit f = fitCircle(pts);
    if (kcmd == 0.0) {
      // full spinning is a screw motion about omega = (kappa, 0, 2 pi/cycle): its axis is
      // tilted by kappa cycle/(2 pi) from the needle axis, so the tip drifts by L times that
      const double drift = 0.15 * kappa * 2e-3 / (2 * pi);
      EXPECT_LT(std::hypot(pts.back().x(), pts.back().y()), 1.05 * drift);
      EXPECT_GT(std::hypot(pts.back().x(), pts.back().y()), 0.95 * drift);
    } else {
      EXPECT_NEAR(1 / f.radius, kcmd, 0.02 * kcmd) << "dc " << dc;
    }
  }
}

TEST(Kinematic, ContinuousSpinKeepsTheNeedleNearTheAxis) {
  KinematicParams par{5.0, 1e-3};
  const Control plan[] = {{0, 0.15, 2 * pi / 1e-3}};
  std::vector<Vec3> pts(kinematicSampleCount(par, plan));
  simulateKinematic(par, Pose{}, plan, pts);
  // screw motion: helix radius kappa/(kappa^2 + w^2) ~ 0.13 um about an axis tilted by
  // kappa/w from the needle axis, so the lateral offset stays below s kappa/w + 2 radius
  const double w = 2 * pi / 1e-3;
  for (const Vec3& p : pts) EXPECT_LT(std::hypot(p.x(), p.y()), p.z() * 5.0 / w + 2 * 5.0 / (w * w) + 1e-12);
}

TEST(Kinematic, SmallOutputBufferIsNotOverrun) {
  KinematicParams par{5.0, 1e-3};
  const Control plan[] = {{0, 0.15}};
  std::vector<Vec3> pts(10, Vec3::Constant(42));
  Pose end;
  EXPECT_EQ(simulateKinematic(par, Pose{}, plan, std::span<Vec3>(pts).first(5), &end), 5);
  EXPECT_EQ(pts[5], Vec3::Constant(42));
  EXPECT_NEAR(end.p.z(), std::sin(0.75) / 5.0, 1e-12);
}
