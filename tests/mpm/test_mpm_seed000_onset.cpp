// Seed 000 section 5.2 reports fracture onset at 4, 15 and 6 mm for phantom groups of different
// stiffness. The model's fracture criterion (section 3.4: neighbouring points in non-adjacent grid
// cells) is kinematic, and the quasi-static problem is homogeneous in the modulus: scaling mu (and
// with it K) by s and the mass scaling by s leaves the wave speed, the time step and every
// acceleration unchanged, so the motion, and the onset depth, are those of the base run and the
// forces are s times its forces. A modulus change alone therefore moves the onset only through
// inertia (docs/validation/mpm.md "Seed 000 section 5: fracture onset").
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "mpm_test_scenario.hpp"

using namespace needlesim;
using namespace needlesim::mpm_test;

namespace {
// The 1 mm cone of MpmEngine.NumericalFractureNearThePathAfterContact in the grid contact, which
// separates pairs here (the CFEMP default separates none on this small block).
std::string onsetScenario(const std::string& mu, const std::string& massScaling) {
  std::string s = replaced(smallScenario("    contact: grid\n", "conical"), "outer_diameter: 1 mm", "outer_diameter: 1 mm\n  bevel_angle: 30 deg");
  s = replaced(s, "length: 6 mm, width: 4 mm, height: 4 mm", "length: 10 mm, width: 5 mm, height: 5 mm");
  s = replaced(s, "to: 3 mm", "to: 7 mm");
  s = replaced(s, "mu: 10 kPa", "mu: " + mu);
  return replaced(s, "mass_scaling: 1e4", "mass_scaling: " + massScaling);
}
double res(const MemorySink& m, const char* k) { return m.results.at(k).value; }
}  // namespace

TEST(MpmSeed000, FractureOnsetIsTheSameWhenModulusAndMassScaleTogether) {
  const MemorySink base = runText(onsetScenario("10 kPa", "1e4"));
  const MemorySink scaled = runText(onsetScenario("40 kPa", "4e4"));
  const double onset = res(base, "fracture_onset_depth");
  std::printf("onset %.4f / %.4f mm, pairs %g / %g, steps %g / %g, final force %.5g / %.5g N\n", onset * 1e3,
              res(scaled, "fracture_onset_depth") * 1e3, res(base, "fracture_pairs"), res(scaled, "fracture_pairs"),
              res(base, "steps"), res(scaled, "steps"), res(base, "final_force"), res(scaled, "final_force"));
  ASSERT_TRUE(std::isfinite(onset));
  // Equal to round-off: the two runs take the same steps to the same positions.
  EXPECT_EQ(res(scaled, "steps"), res(base, "steps"));
  EXPECT_NEAR(res(scaled, "fracture_onset_depth"), onset, 1e-9);
  EXPECT_EQ(res(scaled, "fracture_pairs"), res(base, "fracture_pairs"));
  EXPECT_NEAR(res(scaled, "final_force"), 4.0 * res(base, "final_force"), 1e-6 * res(scaled, "final_force"));
}
