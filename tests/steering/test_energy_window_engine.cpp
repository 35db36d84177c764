// The path-window energy model chosen from a scenario (model.steering.energy_frame)
// gives a circular path, and a thinner needle curves more (seed 002 Fig 22 trend).
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

#include "needlesim/engines/memory_sink.hpp"
#include "needlesim/scenario/reader.hpp"

using namespace needlesim;


TEST(SteeringEnginesEnergyWindow, ScenarioGivesACircularPath) {
  Scenario sc = scenario::readFile(std::string(NEEDLESIM_SOURCE_DIR) +
                                   "/examples/steering/table2_gelC_054_energy_window.yaml");
  ASSERT_EQ(sc.model.steering.energy_frame, "path-window");
  MemorySink s = runInMemory(sc);
  const double whole = s.results.at("radius_whole").value;
  for (const char* k : {"radius_0_50mm", "radius_50_100mm", "radius_100_150mm"})
    EXPECT_NEAR(s.results.at(k).value, whole, 0.05 * whole) << k;
  // Far from straight: a finite radius below a few times the measured 240 mm.
  EXPECT_LT(whole, 1.0);
}

TEST(SteeringEnginesEnergyWindow, ThinnerNeedleCurvesMore) {
  std::string base = R"(tissue:
  block: {length: 200 mm, width: 100 mm, height: 100 mm}
  material: {law: neo-hookean, C10: 7.55 kPa, nu: 0.45}
  interaction: {K_T: 12.61 kN/m^2, toughness: 46.8 kN/m}
needle: {outer_diameter: OD, inner_diameter: 0 mm, length: 200 mm, bevel_angle: 30 deg, youngs_modulus: 50 GPa}
insertion:
  profile: [{insert: {to: 150 mm, speed: 2.5 mm/s}}]
model:
  engine: energy
  steering: {energy_frame: path-window, beta_over_alpha: 0.25, input_force: 15 mN}
)";
  auto radius = [&](const std::string& od) {
    std::string y = base;
    y.replace(y.find("OD"), 2, od);
    return runInMemory(scenario::readText(y, "t.yaml")).results.at("radius_whole").value;
  };
  const double thin = radius("0.3 mm"), thick = radius("0.6 mm");
  EXPECT_LT(thin, thick / 1.5) << thin << " vs " << thick;  // curvature ~ 1/d: about 2x
}
