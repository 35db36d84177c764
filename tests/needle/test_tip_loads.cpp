// Bevel-tip loads, seed 002 eqs 20-26; dimensional analysis, seed 002 eqs 1-3, seed 004 eqs 2-3.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "needlesim/needle/bevel_tip.hpp"
#include "needlesim/needle/section.hpp"

using namespace needlesim::needle;
constexpr double deg = std::numbers::pi / 180.0;

namespace {
TipLoadInput base() { return {9.21e3, 0.46e-3, 31.89 * deg, 0.3 * 31.89 * deg, 2e-3}; }
}  // namespace

TEST(TipLoads, BetaZeroOnlyTheBevelEdgeIsLoaded) {
  // beta = 0: F1 = 0, gamma = alpha, Q = -K_T b^2/2 sin(alpha), M = K_T b^2/2 tan(alpha)
  // (b/3 cos^2 alpha - e sin alpha) with e = d - b/3 sin(alpha) = 2d/3.
  TipLoadInput in = base();
  in.beta = 0;
  const TipLoads t = bevelTipLoads(in);
  const double b = in.diameter / std::sin(in.alpha), K = in.K_T, al = in.alpha;
  EXPECT_EQ(t.F1, 0.0);
  EXPECT_NEAR(t.Q, -K * b * b / 2 * std::sin(al), 1e-15);
  EXPECT_NEAR(t.e, 2 * in.diameter / 3, 1e-15);
  const double M = K * b * b / 2 * std::tan(al) * (b / 3 * std::cos(al) * std::cos(al) - 2 * in.diameter / 3 * std::sin(al));
  EXPECT_NEAR(t.M, M, 1e-18);
  EXPECT_NEAR(t.P, in.P_input - K * b * b / 2 * std::tan(al) * std::sin(al), 1e-15);
}

TEST(TipLoads, BetaEqualsAlphaOnlyTheBottomEdgeIsLoaded) {
  // beta = alpha: gamma = 0, F2 = 0, P = P_input, Q = K_T a^2/2 tan(alpha), M = -K_T a^3/6 tan(alpha)
  TipLoadInput in = base();
  in.beta = in.alpha;
  const TipLoads t = bevelTipLoads(in);
  const double a = in.diameter / std::tan(in.alpha);
  EXPECT_NEAR(t.F2, 0.0, 1e-18);
  EXPECT_DOUBLE_EQ(t.P, in.P_input);
  EXPECT_NEAR(t.Q, in.K_T * a * a / 2 * std::tan(in.alpha), 1e-15);
  EXPECT_NEAR(t.M, -in.K_T * a * a * a / 6 * std::tan(in.alpha), 1e-18);
}

TEST(TipLoads, LinearInInteractionStiffness) {
  TipLoadInput in = base();
  const TipLoads t1 = bevelTipLoads(in);
  in.K_T *= 3.0;
  const TipLoads t3 = bevelTipLoads(in);
  EXPECT_NEAR(t3.Q, 3 * t1.Q, 1e-12 * std::abs(t1.Q));
  EXPECT_NEAR(t3.M, 3 * t1.M, 1e-12 * std::abs(t1.M));
  EXPECT_NEAR(in.P_input - t3.P, 3 * (in.P_input - t1.P), 1e-15);
  in.K_T = 0;
  const TipLoads t0 = bevelTipLoads(in);
  EXPECT_EQ(t0.Q, 0.0);
  EXPECT_EQ(t0.M, 0.0);
}

TEST(TipLoads, QAndMIndependentOfInputForce) {
  TipLoadInput in = base();
  const TipLoads t1 = bevelTipLoads(in);
  in.P_input = 0.5;
  const TipLoads t2 = bevelTipLoads(in);
  EXPECT_EQ(t1.Q, t2.Q);
  EXPECT_EQ(t1.M, t2.M);
  EXPECT_NEAR(t2.P - t1.P, 0.5 - 2e-3, 1e-15);
}

TEST(TipLoads, QChangesSignOnceBetweenTheLimits) {
  // Q < 0 at beta = 0 (bevel edge pushes), Q > 0 at beta = alpha, monotone in between.
  TipLoadInput in = base();
  double prev = -1e9;
  int sign_changes = 0;
  for (int k = 0; k <= 100; ++k) {
    in.beta = in.alpha * k / 100.0;
    const double q = bevelTipLoads(in).Q;
    EXPECT_GT(q, prev);
    if (k > 0 && (q > 0) != (prev > 0)) ++sign_changes;
    prev = q;
  }
  EXPECT_EQ(sign_changes, 1);
}

TEST(TipLoads, RejectsNonPhysicalInput) {
  TipLoadInput in = base();
  in.beta = in.alpha * 1.1;
  EXPECT_THROW(bevelTipLoads(in), std::invalid_argument);
  in = base();
  in.alpha = 95 * deg;
  EXPECT_THROW(bevelTipLoads(in), std::invalid_argument);
}

TEST(Dimensional, GroupsAreDimensionlessAndRho0MatchesEq3) {
  // Scaling every length by s, force by f leaves Pi groups unchanged: E, C10 ~ f/s^2,
  // Gc ~ f/s, I ~ s^4, P ~ f, rho ~ s.
  DimensionalInput in{50e9, Section{50e9, 0.46e-3, 0}.secondMoment(), 0.556, 4e3, 1e4, 0.3, 2e-3, 1e-3, 0.3};
  const DimensionalGroups g = dimensionalGroups(in);
  EXPECT_NEAR(g.rho0, in.Gc * in.Gc / (in.E * in.C10 * std::pow(in.I, 0.25)), 1e-12 * g.rho0);
  EXPECT_NEAR(g.Pi1, in.rho / g.rho0, 1e-12 * g.Pi1);
  const double s = 3.7, f = 0.2;
  DimensionalInput sc = in;
  sc.E *= f / (s * s);
  sc.C10 *= f / (s * s);
  sc.Gc *= f / s;
  sc.I *= s * s * s * s;
  sc.P_input *= f;
  sc.rho *= s;
  sc.u *= s;
  const DimensionalGroups h = dimensionalGroups(sc);
  for (auto [a, b] : {std::pair{g.Pi1, h.Pi1}, {g.Pi2, h.Pi2}, {g.Pi3, h.Pi3}, {g.Pi4, h.Pi4},
                      {g.s004_Pi1, h.s004_Pi1}, {g.s004_Pi2, h.s004_Pi2}, {g.s004_Pi3, h.s004_Pi3}})
    EXPECT_NEAR(a, b, 1e-10 * std::abs(a));
  EXPECT_NEAR(h.rho0, g.rho0 * s, 1e-10 * h.rho0);
}

TEST(Section, SolidAndHollow) {
  const Section s{50e9, 1e-3, 0};
  EXPECT_NEAR(s.secondMoment(), std::numbers::pi * 1e-12 / 64, 1e-25);
  const Section h{50e9, 1e-3, 0.5e-3};
  EXPECT_NEAR(h.secondMoment(), std::numbers::pi * (1e-12 - 0.0625e-12) / 64, 1e-25);
  EXPECT_NEAR(h.area(), std::numbers::pi / 4 * (1e-6 - 0.25e-6), 1e-18);
}

// The eq 25 magnitudes of seed 002 section 3.1 were measured on 15 mm scaled tips (Fig 10).
// F1, F2 (eqs 22-23) integrate K_T (N/m^2) times a displacement (m) over an edge (m): N.
// All lengths scale with d, so Q and M scale as d^2 and d^3: a 0.46 mm needle carries
// (0.46/15)^2 ~ 1/1000 of the scaled tip's Q in the same gel.
TEST(TipLoads, ScaleWithDiameterSquaredAndCube) {
  const double a = 31.89 * deg, b = 0.21 * a, K = 9.21e3;
  const TipLoads big = bevelTipLoads({K, 15e-3, a, b, 0.0});
  const TipLoads real = bevelTipLoads({K, 0.46e-3, a, b, 0.0});
  const double s = 15.0 / 0.46;
  EXPECT_NEAR(big.Q / real.Q, s * s, 1e-9 * s * s);
  EXPECT_NEAR(big.M / real.M, s * s * s, 1e-9 * s * s * s);
  EXPECT_LT(std::abs(real.Q), 2e-3);  // about 1 mN for the Table 2 needles
  EXPECT_GT(std::abs(big.Q), 0.1);    // the order of the Fig 14 forces
}
