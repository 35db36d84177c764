// Tissue regions (tissue/regions.hpp): layers then inclusions, each with its material, friction and
// toughness; the region of a point is the last inclusion holding it, else the layer at its depth.
#include <gtest/gtest.h>

#include "needlesim/tissue/regions.hpp"

using namespace needlesim;

namespace {

// Two layers (2 mm skin, 8 mm gel) and two overlapping spheres in the gel; the later one is laid over.
TissueSpec twoLayersTwoSpheres() {
  TissueSpec t;
  t.length = 10e-3;
  LayerSpec skin, gel;
  skin.name = "skin", skin.thickness = 2e-3, skin.friction.coefficient = 0.4, skin.toughness = 50;
  skin.material.law = "neo-hookean", skin.material.params = {{"C10", 20e3}, {"nu", 0.45}};
  gel.name = "gel", gel.thickness = 8e-3, gel.friction.coefficient = 0.25;
  gel.material.law = "neo-hookean", gel.material.params = {{"C10", 3.5e3}, {"nu", 0.45}};
  t.layers = {skin, gel};
  InclusionSpec a, b;
  a.name = "a", a.x = 5e-3, a.radius = 1e-3, a.friction_coefficient = 0.1, a.toughness = 7;
  b.name = "b", b.x = 5.8e-3, b.radius = 0.5e-3, b.friction_coefficient = 0.25;
  t.inclusions = {a, b};
  return t;
}

}  // namespace

TEST(TissueRegions, LayersThenInclusionsWithTheirFrictionAndToughness) {
  const TissueSpec t = twoLayersTwoSpheres();
  const auto r = tissue::regions(t);
  ASSERT_EQ(r.size(), 4u);
  EXPECT_EQ(r[0].name, "skin");
  EXPECT_EQ(r[1].field, "tissue.layers[1]");
  EXPECT_EQ(r[3].field, "tissue.inclusions[1]");
  EXPECT_FALSE(r[1].inclusion);
  EXPECT_TRUE(r[2].inclusion);
  EXPECT_EQ(r[0].material.params.at("C10"), 20e3);
  EXPECT_EQ(tissue::regionFrictions(r), (std::vector<double>{0.4, 0.25, 0.1, 0.25}));
  EXPECT_EQ(r[0].toughness, 50);
  EXPECT_EQ(r[2].toughness, 7);
  EXPECT_FALSE(tissue::uniformFriction(r));
  auto same = r;
  for (auto& x : same) x.friction = 0.3;
  EXPECT_TRUE(tissue::uniformFriction(same));
}

TEST(TissueRegions, APointIsInTheLastInclusionHoldingItElseInTheLayerAtItsDepth) {
  const TissueSpec t = twoLayersTwoSpheres();
  EXPECT_EQ(tissue::regionAt(t, 1e-3, 0, 0), 0);       // skin
  EXPECT_EQ(tissue::regionAt(t, 3e-3, 0, 0), 1);       // gel
  EXPECT_EQ(tissue::regionAt(t, 4.5e-3, 0, 0), 2);     // sphere a only
  EXPECT_EQ(tissue::regionAt(t, 5.7e-3, 0, 0), 3);     // in both: b is laid over a
  EXPECT_EQ(tissue::regionAt(t, 5e-3, 2e-3, 0), 1);    // beside both
  EXPECT_EQ(tissue::regionAt(t, 12e-3, 0, 0), 1);      // beyond the block: the last layer
}
