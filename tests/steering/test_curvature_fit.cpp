// Radius-of-curvature fitting (seed 002 section 5.1, Table 2 layout).
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "needlesim/engines/steering/curvature_fit.hpp"

using namespace needlesim::steering;
using Vec3 = Eigen::Vector3d;

TEST(CurvatureFit, ExactCircleArcInATiltedPlane) {
  const double R = 0.3;
  const Vec3 c(0.01, -0.02, 0.03);
  const Vec3 e1 = Vec3(1, 2, 2).normalized(), e2 = Vec3(2, -1, 0).normalized();
  std::vector<Vec3> pts;
  for (int i = 0; i <= 150; ++i) {
    const double t = i * 1e-3 / R;  // 150 mm of arc
    pts.push_back(c + R * (std::cos(t) * e1 + std::sin(t) * e2));
  }
  const CircleFit f = fitCircle(pts);
  EXPECT_NEAR(f.radius, R, 1e-10);
  EXPECT_NEAR((f.centre - c).norm(), 0, 1e-9);
  EXPECT_LT(f.rms, 1e-12);
  const SectionRadii s = sectionRadii(pts);
  for (double r : s.rho) EXPECT_NEAR(r, R, 1e-8);
  EXPECT_NEAR(s.whole, R, 1e-10);
}

TEST(CurvatureFit, NoisyArcLikeCameraTracking) {
  // 0.2 mm measurement noise on a 300 mm radius, 50 mm sections: the radius is still
  // found within a few per cent on the whole path (sagitta 9.4 mm >> noise).
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0.0, 0.2e-3);
  std::vector<Vec3> pts;
  for (int i = 0; i <= 300; ++i) {
    const double t = i * 0.5e-3 / 0.3;
    pts.push_back(Vec3(0, -0.3 * (1 - std::cos(t)), 0.3 * std::sin(t)) +
                  Vec3(noise(rng), noise(rng), noise(rng)));
  }
  EXPECT_NEAR(fitCircle(pts).radius, 0.3, 0.02 * 0.3);
}

TEST(CurvatureFit, StraightLineIsInfinite) {
  std::vector<Vec3> pts;
  for (int i = 0; i < 50; ++i) pts.push_back(Vec3(0, 0, i * 1e-3));
  EXPECT_TRUE(std::isinf(fitCircle(pts).radius));
  EXPECT_TRUE(std::isinf(fitCircle(std::span<const Vec3>(pts).first(2)).radius));
}
