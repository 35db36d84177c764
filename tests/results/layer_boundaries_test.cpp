// Layer boundaries on a plot against depth: one marker per interface, at the summed
// thicknesses along the needle (over sin(entry angle)), in the axis' unit, from its origin.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "needlesim/results/layer_boundaries.hpp"

using namespace needlesim;

TEST(LayerBoundaries, MarkersAtTheInterfacesAlongTheNeedleInTheAxisUnit) {
  Scenario sc;
  for (auto [name, t] : {std::pair{"skin", 0.002}, {"fat", 0.010}, {"muscle", 0.020}}) {
    LayerSpec l;
    l.name = name;
    l.thickness = t;
    sc.tissue.layers.push_back(l);
  }
  sc.insertion.entry_angle = std::numbers::pi / 3;  // 60 deg: 1/sin = 1.1547
  io::Plot p{"F", "needle displacement [mm]", "force [N]", {}};
  results::markLayerBoundaries(p, sc, -0.0005);  // x = 0 at a tip 0.5 mm outside
  ASSERT_EQ(p.xmarkers.size(), 2u);
  const double along = 1 / std::sin(std::numbers::pi / 3);
  EXPECT_NEAR(p.xmarkers[0].x, (0.002 * along + 0.0005) * 1e3, 1e-12);
  EXPECT_NEAR(p.xmarkers[1].x, (0.012 * along + 0.0005) * 1e3, 1e-12);
  EXPECT_EQ(p.xmarkers[0].label, "skin | fat");
  EXPECT_EQ(p.xmarkers[1].label, "fat | muscle");

  io::Plot m{"F", "tip depth [m]", "force [N]", {}};
  results::markLayerBoundaries(m, sc);
  EXPECT_NEAR(m.xmarkers[1].x, 0.012 * along, 1e-15);

  sc.tissue.layers.resize(1);
  io::Plot one{"F", "tip depth [mm]", "force [N]", {}};
  results::markLayerBoundaries(one, sc);
  EXPECT_TRUE(one.xmarkers.empty());
}
