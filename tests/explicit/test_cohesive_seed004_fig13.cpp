// Seed 004 section IV-B, Fig 13, at the nearly blunt 80 deg bevel (examples/cohesive/seed004_fig13_bevel_2d.yaml
// with the 80 deg row of examples/studies/cohesive_seed004_fig13.yaml; docs/validation/cohesive.md
// "Section IV-B, Fig 13"). The sharp point meets the bevel-side lip's entry corner node head on; the
// 0.35 mm face pushes it forward. On needle::queryNeedle's continued bevel face (surface_mesh.cpp
// bevelFaceContinued) its depth is continuous across the cut line, so the needle's work equals what
// the tissue takes up, as for the other angles (1.5-9.6 %). With the lower wall as the lip's boundary
// the node gained k d^2 / 2 at each crossing (0.05 mm behind the point: d ~ 0.05 mm): 77 % off at 10 mm/s,
// 660 % at 1.25 mm/s (a penalty energy per crossing, not an impact).
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>

#include "needlesim/engines/memory_sink.hpp"
#include "needlesim/scenario/reader.hpp"
#include "needlesim/study/with_values.hpp"

using namespace needlesim;

namespace {
std::string exampleText() {
  std::ifstream f(std::string(NEEDLESIM_SOURCE_DIR) + "/examples/cohesive/seed004_fig13_bevel_2d.yaml");
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

// The study's 80 deg row: pushed to the bevel length 2 mm / tan(80 deg) = 0.353 mm + 0.5 mm.
MemorySink runBevel80(const std::string& speed) {
  const std::string y = study::withValuesYaml(exampleText(),
                                              {{"needle.bevel_angle", "80 deg"},
                                               {"insertion.profile[0].insert.to", "0.853 mm"},
                                               {"insertion.profile[0].insert.speed", speed}},
                                              SourceLocation{"test_cohesive_seed004_fig13.cpp", 0, 0}, "field");
  return runInMemory(scenario::readText(y, "seed004_fig13_bevel80.yaml"));
}
double res(const MemorySink& m, const char* k) { return m.results.at(k).value; }

// The 5 % the 3D cone insertion asserts (CohesiveThreeD), the level of the study's other angles.
constexpr double kNeedleBalanceTolerance = 0.05;
}  // namespace

// 10 mm/s as in the study (0.2 s on one core): the balance, and kinetic / internal at the other rows'
// level (0.05-0.17; 0.73 with the crossings' energy shaking the surface).
TEST(CohesiveSeed004, Fig13NearlyBluntBevelBalancesTheNeedleWork) {
  const MemorySink r = runBevel80("10 mm/s");
  std::printf("needle balance %.4g, kinetic/internal %.3g, needle work %.4g J, viscous %.4g J\n",
              res(r, "needle_energy_balance_error"), res(r, "kinetic_internal_ratio_max"), res(r, "needle_work"),
              res(r, "viscous_dissipation"));
  EXPECT_LT(res(r, "needle_energy_balance_error"), kNeedleBalanceTolerance);
  EXPECT_LT(res(r, "kinetic_internal_ratio_max"), 0.3);
  // bulk viscosity dissipates almost nothing (5e-9 of 9e-6 J; 5.9e-6 J with the crossings' shaking)
  EXPECT_LT(res(r, "viscous_dissipation"), 0.01 * res(r, "needle_work"));
}

// 8 times slower (1.2 s): the same balance, so no impact term is missing from it (with the lower wall as
// the lip's boundary: 660 %, the energy per crossing adding up over 8 times as many steps).
TEST(CohesiveSeed004, Fig13NearlyBluntBevelBalancesTheNeedleWorkSlowly) {
  const MemorySink r = runBevel80("1.25 mm/s");
  std::printf("needle balance %.4g, kinetic/internal %.3g\n", res(r, "needle_energy_balance_error"),
              res(r, "kinetic_internal_ratio_max"));
  EXPECT_LT(res(r, "needle_energy_balance_error"), kNeedleBalanceTolerance);
  EXPECT_LT(res(r, "kinetic_internal_ratio_max"), 0.1);
}
