// Modified Karnopp friction (seed 003 eq 3.23, contact/karnopp.hpp): the
// branches, the static band and the derivatives against central finite
// differences (tolerance: the branches are affine, so a central difference
// is exact up to rounding, eps |f| / h ~ 1e-10 relative with h = 1e-6 x the
// argument; 1e-7 relative leaves three orders of margin).
#include <gtest/gtest.h>

#include <cmath>

#include "needlesim/contact/karnopp.hpp"

using namespace needlesim;

namespace {

FrictionSpec symmetric(double C, double b, double band) {
  FrictionSpec f;
  f.C_p = f.C_n = C;
  f.b_p = f.b_n = b;
  f.static_band = band;
  // static limits continuous with the slip branches at the band edges
  f.D_p = f.D_n = C + b * band / 2;
  return f;
}

}  // namespace

TEST(Karnopp, BranchesOfEq323) {
  FrictionSpec f = symmetric(3.0, 300.0, 2e-4);  // D = 3.03 N/m
  // Sliding forward: C_p + b_p v.
  EXPECT_DOUBLE_EQ(contact::karnoppPerLength(f, 3e-3, 0.0), 3.0 + 300.0 * 3e-3);
  // Sliding backward: C_n sgn(v) + b_n v, negative.
  EXPECT_DOUBLE_EQ(contact::karnoppPerLength(f, -3e-3, 0.0), -3.0 - 300.0 * 3e-3);
  // Static band: follows the applied force inside the limits ...
  EXPECT_DOUBLE_EQ(contact::karnoppPerLength(f, 0.0, 1.5), 1.5);
  EXPECT_DOUBLE_EQ(contact::karnoppPerLength(f, 0.0, -2.0), -2.0);
  // ... and saturates at the static limits.
  EXPECT_DOUBLE_EQ(contact::karnoppPerLength(f, 0.0, 10.0), f.D_p);
  EXPECT_DOUBLE_EQ(contact::karnoppPerLength(f, 0.0, -10.0), -f.D_n);
}

TEST(Karnopp, ContinuousAtTheBandEdgesWhenStaticLimitMatchesDynamic) {
  FrictionSpec f = symmetric(3.0, 300.0, 2e-4);
  const double h = f.static_band / 2, eps = 1e-12;
  EXPECT_NEAR(contact::karnoppPerLength(f, h - eps, 1e9), contact::karnoppPerLength(f, h, 0.0), 1e-9);
  EXPECT_NEAR(contact::karnoppPerLength(f, -h + eps, -1e9), contact::karnoppPerLength(f, -h, 0.0), 1e-9);
}

// Asymmetric coefficients: each branch takes its own (C_p, b_p, D_p forward; C_n, b_n, D_n back).
TEST(Karnopp, StaticBandSticksBetweenTheAsymmetricLimits) {
  FrictionSpec f;
  f.C_p = 3.0, f.b_p = 300.0, f.C_n = 2.0, f.b_n = 100.0, f.D_p = 4.0, f.D_n = 1.0, f.static_band = 1e-4;
  for (const double v : {-4e-5, 0.0, 4.9e-5}) {  // |v| < band / 2
    EXPECT_EQ(contact::karnoppPerLength(f, v, 3.9), 3.9);
    EXPECT_EQ(contact::karnoppPerLength(f, v, -0.9), -0.9);
    EXPECT_EQ(contact::karnoppPerLength(f, v, 4.1), 4.0);
    EXPECT_EQ(contact::karnoppPerLength(f, v, -1.1), -1.0);
  }
  EXPECT_DOUBLE_EQ(contact::karnoppPerLength(f, 5e-5, 0.0), 3.0 + 300.0 * 5e-5);   // band edge: slides
  EXPECT_DOUBLE_EQ(contact::karnoppPerLength(f, -5e-5, 0.0), -2.0 - 100.0 * 5e-5);
}

TEST(Karnopp, DerivativesMatchFiniteDifferences) {
  FrictionSpec f;
  f.C_p = 3.0, f.b_p = 300.0, f.C_n = 2.0, f.b_n = 100.0, f.D_p = 4.0, f.D_n = 1.0, f.static_band = 1e-4;
  // (v, F_a): forward and backward slip, the band inside and beyond each static limit (away from the kinks)
  for (const auto& [v, Fa] : {std::pair{3e-3, 0.5}, std::pair{-2e-3, 0.5}, std::pair{1e-5, 2.0}, std::pair{-1e-5, -0.5},
                              std::pair{1e-5, 6.0}, std::pair{1e-5, -3.0}}) {
    const contact::KarnoppSlope s = contact::karnoppSlope(f, v, Fa);
    const double hv = 1e-6 * std::abs(v), ha = 1e-6 * std::abs(Fa);
    const double dv = (contact::karnoppPerLength(f, v + hv, Fa) - contact::karnoppPerLength(f, v - hv, Fa)) / (2 * hv);
    const double da = (contact::karnoppPerLength(f, v, Fa + ha) - contact::karnoppPerLength(f, v, Fa - ha)) / (2 * ha);
    EXPECT_NEAR(s.v, dv, 1e-7 * std::max(std::abs(dv), 1.0)) << v << " " << Fa;
    EXPECT_NEAR(s.applied, da, 1e-7) << v << " " << Fa;
  }
  EXPECT_EQ(contact::karnoppSlope(f, 3e-3, 0.0).v, f.b_p);
  EXPECT_EQ(contact::karnoppSlope(f, -3e-3, 0.0).v, f.b_n);
  EXPECT_EQ(contact::karnoppSlope(f, 0.0, 1.0).applied, 1.0);
}
