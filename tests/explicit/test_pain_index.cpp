// Seed 001 pain index (eqs 7-8) against a hand-computed force curve.
#include <gtest/gtest.h>

#include <cmath>

#include "needlesim/core/error.hpp"
#include "needlesim/engines/explicit/pain_index.hpp"

using namespace needlesim;
using namespace needlesim::explicit_fe;

TEST(PainIndex, AnnulusAreaOfSeed001Needle) {
  // OD 2.77 mm, ID 2.16 mm: pi (1.385^2 - 1.08^2) mm^2 = pi x 0.751825 mm^2 = 2.361928 mm^2
  EXPECT_NEAR(needleAnnulusArea(2.77e-3, 2.16e-3), 2.361928e-6, 1e-12);
  EXPECT_NEAR(needleAnnulusArea(2e-3, 0.0), M_PI * 1e-6, 1e-15);  // solid: pi R^2
}

TEST(PainIndex, BasicStressIsNeoHookeanCompressionAtThirtyPercent) {
  // Incompressible neo-Hookean, nominal stress 2 C10 (l - l^-2) (seed 004 eq 10 / l), l = 0.7:
  // 2 x 5 kPa x (0.7 - 2.040816) = -13.408 kPa
  materials::MaterialSpec spec;
  spec.law = "neo-hookean";
  spec.params = {{"C10", 5e3}, {"nu", 0.495}};
  const double l = 0.7, hand = 2 * 5e3 * (1.0 / (l * l) - l);
  EXPECT_NEAR(painBasicStress(spec), hand, 1e-6 * hand);
}

TEST(PainIndex, PeakAndMeanOfHandForceCurve) {
  // F = 0, 1, 4, 2 N at t = 0, 1, 2, 3 s; area 2e-6 m^2; sigma* = 1e5 Pa
  // peak sigma = 4 / 2e-6 = 2e6 Pa -> PDI 20; mean F = (0.5 + 2.5 + 3) / 3 = 2 N -> PDI 10
  PainIndex p = painIndex({0, 1, 2, 3}, {0, 1, 4, 2}, 2e-6, 1e5);
  EXPECT_DOUBLE_EQ(p.peakStress, 2e6);
  EXPECT_NEAR(p.peak, 20.0, 1e-12);
  EXPECT_NEAR(p.mean, 10.0, 1e-12);
  // a pulling (negative) force presses nothing: counts as 0
  PainIndex q = painIndex({0, 1}, {-3, -1}, 2e-6, 1e5);
  EXPECT_EQ(q.peak, 0.0);
  EXPECT_THROW(painIndex({0, 1}, {1, 1}, 0.0, 1e5), Error);
}
