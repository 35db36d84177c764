// Seed 001 pain index (eqs 7-8) against a hand-computed force curve and its engine wiring.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "needlesim/core/error.hpp"
#include "needlesim/engines/explicit/pain_index.hpp"
#include "needlesim/engines/memory_sink.hpp"
#include "engine_tables.hpp"
#include "needlesim/scenario/reader.hpp"

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

// Engine wiring: a small 3D hollow-needle insertion reports the PDI of its own force record
// (peak axial force / annulus area / sigma*), sigma* of its neo-Hookean layer in closed form.
TEST(PainIndex, ExplicitEngineReportsPdiOfItsForceRecord) {
  const char* yaml = R"(
name: pdi_engine
tissue:
  block: {length: 8 mm, width: 10 mm, height: 10 mm}
  material: {law: neo-hookean, C10: 3.6 kPa, nu: 0.495, density: 1060 kg/m^3}
  friction: {coefficient: 0.3}
needle: {outer_diameter: 2.77 mm, inner_diameter: 2.16 mm, length: 30 mm, bevel_angle: 12 deg, tip: bevel, youngs_modulus: 50 GPa}
insertion:
  entry_angle: 90 deg
  start_depth: -0.5 mm
  profile:
    - insert: {to: 2 mm, speed: 10 mm/s}
model:
  engine: explicit
  explicit: {dimension: 3d, element: hex8, element_size: 1 mm, max_element_size: 3 mm, core_width: 6 mm, mass_scaling: 100, tip_friction: 0}
output: {interval: 10 ms}
)";
  MemorySink m = runInMemory(scenario::readText(yaml, "<pdi>"));
  const auto f = explicit_test::column(m, "forces", "force_total");
  double peak = 0;
  for (double v : f) peak = std::max(peak, v);
  ASSERT_GT(peak, 0.0);  // the needle met the tissue
  const double l = 0.7, sigmaStar = 2 * 3.6e3 * (1.0 / (l * l) - l);  // 9653.9 Pa
  const double area = M_PI * (1.385e-3 * 1.385e-3 - 1.08e-3 * 1.08e-3);
  EXPECT_NEAR(m.results.at("pain_basic_stress").value, sigmaStar, 1e-6 * sigmaStar);
  EXPECT_NEAR(m.results.at("pain_index_peak").value, peak / area / sigmaStar, 1e-9 * peak / area / sigmaStar);
  EXPECT_LT(m.results.at("pain_index_mean").value, m.results.at("pain_index_peak").value);
}
