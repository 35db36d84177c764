// Beam-on-elastic-foundation steering model against closed forms.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "needlesim/engines/steering/beam_foundation.hpp"
#include "needlesim/engines/steering/curvature_fit.hpp"
#include "needlesim/engines/steering/table2.hpp"
#include "needlesim/needle/section.hpp"

using namespace needlesim::steering;

namespace {
const double EI = needlesim::needle::Section{50e9, 0.46e-3, 0}.EI();  // 1.1e-4 N m^2
constexpr double KT = 9.21e3, Q = -0.8e-3, M = 5e-8;

std::vector<Vec3> run(double h, double L, double Qv = Q, double Mv = M, double flip_at = -1,
                      double bevel = 0.0) {
  BeamFoundationModel m({EI, KT, Qv, Mv, 0.0, h, L + 2 * h});
  m.reset(Pose{}, bevel);
  const int n = static_cast<int>(std::lround(L / h));
  for (int i = 0; i < n; ++i) {
    if (flip_at > 0 && std::abs(i * h - flip_at) < h / 2) m.rotateBevel(std::numbers::pi);
    m.advance();
  }
  return {m.path().begin(), m.path().end()};
}
}  // namespace

TEST(BeamFoundation, FirstIncrementIsACantilever) {
  // One free element of length h: w = Q h^3/3EI + M h^2/2EI (PL^3/3EI, ML^2/2EI).
  const double h = 2e-3;
  const auto p = run(h, h);
  EXPECT_NEAR(p.back().y(), Q * h * h * h / (3 * EI) + M * h * h / (2 * EI), 1e-15);
}

TEST(BeamFoundation, SymmetricTipGoesStraight) {
  for (const Vec3& x : run(1e-3, 0.15, 0.0, 0.0)) {
    EXPECT_EQ(x.x(), 0.0);
    EXPECT_EQ(x.y(), 0.0);
  }
}

TEST(BeamFoundation, SteadyCurvatureMatchesHetenyiClosedFormAndConverges) {
  // kappa = (M + Q/lambda)/EI (docs/models/steering.md). Fit over 150-300 mm, after the
  // entry transient (1/lambda = 15 mm) has died out. Error is O(h): < 3 % at 1 mm,
  // < 0.5 % at 0.25 mm, and it falls monotonically with h.
  const double k = beamFoundationSteadyCurvature(EI, KT, Q, M);
  ASSERT_LT(k, 0.0);  // Q < 0 pushes towards -y
  double prev = 1e9;
  for (double h : {2e-3, 1e-3, 0.5e-3, 0.25e-3}) {
    const auto p = run(h, 0.3);
    const double kf = 1.0 / fitCircleSection(p, 0.15, 0.3).radius;
    const double err = std::abs(kf - std::abs(k)) / std::abs(k);
    EXPECT_LT(err, prev) << h;
    prev = err;
    if (h <= 1e-3) {
      EXPECT_LT(err, 0.03) << h;
    }
    if (h <= 0.25e-3) {
      EXPECT_LT(err, 0.005) << h;
    }
    EXPECT_LT(p.back().y(), 0.0);
  }
}

TEST(BeamFoundation, CurvatureScalesWithLoadAndStiffness) {
  // doubling Q (M = 0) doubles the curvature; 16x K_T halves lambda^-1, halving Q/lambda
  const double h = 0.5e-3;
  const double k1 = 1 / fitCircleSection(run(h, 0.3, Q, 0), 0.15, 0.3).radius;
  const double k2 = 1 / fitCircleSection(run(h, 0.3, 2 * Q, 0), 0.15, 0.3).radius;
  EXPECT_NEAR(k2 / k1, 2.0, 0.01);
  const double kA = beamFoundationSteadyCurvature(EI, KT, Q, 0), kB = beamFoundationSteadyCurvature(EI, 16 * KT, Q, 0);
  EXPECT_NEAR(kB / kA, 0.5, 1e-12);
}

TEST(BeamFoundation, FlipHalfwayGivesAnSCurve) {
  const double h = 1e-3;
  const auto p = run(h, 0.4, 4 * Q, 0, 0.2);
  const auto first = fitCircleSection(p, 0.1, 0.2), second = fitCircleSection(p, 0.3, 0.4);
  const double k = std::abs(beamFoundationSteadyCurvature(EI, KT, 4 * Q, 0));
  EXPECT_NEAR(1 / first.radius, k, 0.05 * k);
  EXPECT_NEAR(1 / second.radius, k, 0.05 * k);
  // the centres lie on opposite sides of the path
  EXPECT_LT(first.centre.y(), p[150].y());
  EXPECT_GT(second.centre.y(), p[350].y());
}

TEST(BeamFoundation, BevelRotationSteersIn3D) {
  // bevel at 90 deg: bevel +y becomes z x y = -x of the entry frame; Q < 0 pushes to +x
  const auto p = run(1e-3, 0.15, Q, 0, -1, std::numbers::pi / 2);
  EXPECT_GT(p.back().x(), 1e-4);
  // out-of-plane motion only from rounding (cos(pi/2) = 6e-17 amplified by the frames)
  EXPECT_NEAR(p.back().y(), 0.0, 1e-5 * p.back().x());
}

TEST(BeamFoundation, NeedleShapeStaysInItsChannel) {
  BeamFoundationModel m({EI, KT, Q, M, 0.0, 1e-3, 0.2});
  m.reset(Pose{});
  for (int i = 0; i < 150; ++i) m.advance();
  std::vector<Vec3> shape;
  m.shape(shape);
  ASSERT_EQ(shape.size(), 151u);
  const auto path = m.path();
  double maxdev = 0;
  for (size_t j = 0; j < shape.size(); ++j) maxdev = std::max(maxdev, (shape[j] - path[j]).norm());
  // deviations are of order Q/(K_T) * lambda ~ 0.1 mm at most
  EXPECT_LT(maxdev, 2e-4);
  EXPECT_GT(maxdev, 0.0);
}

// Problem (b) of issue 4: with eq 25's Q the radii were 14-20x too large. Seed 002 section 5
// does not feed eq 25 to its model: it drives it with P_input through the sub-step-1 roller,
// whose transverse reaction is P_input/tan(beta) (12-34 mN for the section 5.2 inputs).
// With that load and no fitting, every Table 2 radius is within a factor 3 of the measured
// one and the mean deviation is below 100 %; with eq 25 every radius is over 10x too large.
TEST(BeamFoundation, RollerTipLoadGivesTable2RadiiOfTheMeasuredSize) {
  double sum = 0;
  for (const auto& c : needlesim::steering::table2Cases()) {
    const auto r = needlesim::steering::runTable2Case(c, "beam-foundation");
    EXPECT_GT(r.rho_pred, c.rho_exp / 3) << c.gel << " " << c.diameter;
    EXPECT_LT(r.rho_pred, c.rho_exp * 4) << c.gel << " " << c.diameter;
    sum += std::abs(r.rho_pred - c.rho_exp) / c.rho_exp;
    const auto e = needlesim::steering::runTable2Case(c, "beam-foundation-edges");
    EXPECT_GT(e.rho_pred, 10 * c.rho_exp) << c.gel << " " << c.diameter;
  }
  EXPECT_LT(sum / 12, 1.0);
}

TEST(BeamFoundation, ThinnerNeedlesCurveMoreAtTheSameRollerLoad) {
  // Table 2 trend (thinner needles steer more): kappa = Q/(lambda EI) ~ d^-3
  double last = 0;
  for (double d : {0.54e-3, 0.46e-3, 0.36e-3}) {
    const double EI = needlesim::needle::Section{50e9, d, 0}.EI();
    const double k = needlesim::steering::beamFoundationSteadyCurvature(EI, 10e3, -10e-3, 0.0);
    EXPECT_LT(k, last);  // more negative = more curvature towards the bevel
    last = k;
  }
}
