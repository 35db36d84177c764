// Penalty laws of contact/penalty.hpp: closed forms, and the tangent and the
// force as derivatives (of the force and of the stored energy) against
// central finite differences. Tolerance: step h = 1e-6 x the overlap on a
// smooth branch: truncation h^2 |f'''| / 6 (relative ~1e-11 for the
// barrier's (G/r)^6 at r >= d/4) plus rounding eps |f| / h (~1e-10); 1e-7
// relative is three orders above both.
#include <gtest/gtest.h>

#include <cmath>

#include "needlesim/contact/penalty.hpp"

using namespace needlesim::contact;

namespace {
constexpr double kFdTol = 1e-7;
}  // namespace

TEST(Penalty, LinearForceAndSlope) {
  const double k = 2.5e4;
  EXPECT_EQ(penaltyForce(k, 1e-4), k * 1e-4);
  EXPECT_EQ(penaltySlope(k, 1e-4), k);
  EXPECT_EQ(penaltyEnergy(k, 1e-4), 0.5 * k * 1e-8);
  // separated (or just touching): no force, no stiffness, no energy
  for (const double g : {0.0, -1e-4}) {
    EXPECT_EQ(penaltyForce(k, g), 0.0);
    EXPECT_EQ(penaltySlope(k, g), 0.0);
    EXPECT_EQ(penaltyEnergy(k, g), 0.0);
  }
  // derivatives: dU/dg = f, df/dg = k
  const double g = 3e-4, h = 1e-6 * g;
  EXPECT_NEAR((penaltyEnergy(k, g + h) - penaltyEnergy(k, g - h)) / (2 * h), penaltyForce(k, g), kFdTol * penaltyForce(k, g));
  EXPECT_NEAR((penaltyForce(k, g + h) - penaltyForce(k, g - h)) / (2 * h), penaltySlope(k, g), kFdTol * k);
}

// The explicit FE's k = factor m / dt^2: 10 x 2 g / (1 us)^2 = 2e10 N/m.
TEST(Penalty, MassPenaltyOfTheExplicitSolver) {
  EXPECT_DOUBLE_EQ(massPenalty(10.0, 2e-3, 1e-6), 2e10);
  EXPECT_EQ(massPenalty(10.0, 2e-3, 1e-6), 10.0 / (1e-6 * 1e-6) * 2e-3);  // the solver's order of operations
}

// The MPM pair law: linear to the onset 0.3 d, then the barrier; f(d/2) = k d/2 (0.7/0.5)^6 = 3.76 k d.
TEST(Penalty, PairLawClosedForms) {
  const double k = 1e3, d = 4e-4;
  EXPECT_EQ(pairPenaltyForce(k, 0.1 * d, d), k * 0.1 * d);
  EXPECT_EQ(pairPenaltyTangent(k, 0.1 * d, d), k);
  EXPECT_EQ(pairPenaltyEnergy(k, 0.1 * d, d), 0.5 * k * 0.1 * d * 0.1 * d);
  EXPECT_NEAR(pairPenaltyForce(k, 0.5 * d, d), k * 0.5 * d * std::pow(1.4, 6), 1e-12 * k * d);
  // continuous at the onset (force and energy), the slope steps up to k (1 + 6 delta_s / G) = 3.57 k
  const double s = kPairOnset * d, e = 1e-9 * d;
  EXPECT_NEAR(pairPenaltyForce(k, s + e, d), pairPenaltyForce(k, s, d), 1e-8 * k * d);
  EXPECT_NEAR(pairPenaltyEnergy(k, s + e, d), pairPenaltyEnergy(k, s, d), 1e-8 * k * d * d);
  EXPECT_NEAR(pairPenaltyTangent(k, s + e, d), k * (1 + 6 * 0.3 / 0.7), 1e-6 * k);
}

TEST(Penalty, PairLawDerivativesMatchFiniteDifferences) {
  const double k = 1e3, d = 4e-4;
  for (const double x : {0.05, 0.2, 0.35, 0.5, 0.75}) {  // both branches, away from the onset 0.3
    const double delta = x * d, h = 1e-6 * delta;
    const double f = pairPenaltyForce(k, delta, d), kt = pairPenaltyTangent(k, delta, d);
    const double dU = (pairPenaltyEnergy(k, delta + h, d) - pairPenaltyEnergy(k, delta - h, d)) / (2 * h);
    const double df = (pairPenaltyForce(k, delta + h, d) - pairPenaltyForce(k, delta - h, d)) / (2 * h);
    EXPECT_NEAR(dU, f, kFdTol * f) << "delta/d " << x;
    EXPECT_NEAR(df, kt, kFdTol * kt) << "delta/d " << x;
  }
}
