// Cylindrical cohesive sleeve (mesh_sleeve.cpp, cohesive_surface.cpp fromQuads,
// cohesive_sleeve.cpp; docs/models/cohesive.md "Sleeve seam", docs/validation/cohesive.md
// "Sleeve seam"): the O-grid fills the block, the sleeve quads carry the cylinder's area,
// pulling the core out (mode II) or pushing it apart radially (mode I) dissipates
// G_c x sleeve area, and the annular wedge rule of a hollow bevel needle.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "needlesim/core/error.hpp"
#include "needlesim/engines/explicit/cohesive.hpp"
#include "needlesim/engines/explicit/cohesive_sleeve.hpp"
#include "needlesim/engines/explicit/mesh_sleeve.hpp"
#include "needlesim/engines/explicit/solver.hpp"

using namespace needlesim;
using namespace needlesim::explicit_fe;

namespace {

materials::MaterialSpec linearSpec(double E) {
  materials::MaterialSpec ms;
  ms.law = "linear";
  ms.params = {{"E", E}, {"nu", 0.3}};
  ms.density = 1000;
  return ms;
}

SleeveMeshSpec smallSpec(double depth) {
  SleeveMeshSpec sp;
  sp.width = 10e-3;
  sp.height = 8e-3;
  sp.axisY = 0.5e-3;
  sp.radius = 1.2e-3;
  sp.perQuarter = 4;
  sp.coreLayers = 2;
  sp.radialSize = 0.3e-3;
  sp.maxSize = 2e-3;
  for (int k = 0; k <= 8; ++k) sp.xs.push_back(0.5e-3 * k);
  sp.sleeveDepth = depth;
  return sp;
}

// polygon (chord) perimeter of the circle with 4 nq sides
double polygonPerimeter(const SleeveMeshSpec& sp) {
  const int M = 4 * sp.perQuarter;
  return 2 * M * sp.radius * std::sin(M_PI / M);
}

CohesiveLaw sleeveLaw() {
  CohesiveLaw l;
  l.stiffness = 1e9;
  l.strength = 1e4;
  l.energy = 2.0;
  l.shearEnergy = 4.0;  // G_IIc = 2 G_Ic: a wrong mode split changes the dissipation
  return l;
}

// Core nodes (r <= r_s, originals) move rigidly: axial (mode II) or radially expanding (mode I, the
// sleeve opening at v); the outer tissue is held. D must equal G x sleeve area.
double kinematicSeparation(bool modeI, double& area, int& open, int& pairs) {
  const auto sp = smallSpec(10.0);  // split through the whole length: the core is a separate body
  SleeveMesh sm = sleeveBlock(sp);
  const Mesh& m = sm.mesh;
  ExplicitSolver s(m, {Material::fromSpec(linearSpec(1e6))});
  s.setCohesive(CohesiveInterface::fromQuads(m, sm.pairs, {sleeveLaw()}, sm.quads, sm.quadNormals,
                                             Eigen::Vector3d::UnitX()));
  std::vector<char> copy(m.nodes(), 0);
  for (auto [a, b] : sm.pairs) copy[b] = 1;
  const double v = 0.5;  // prescribed motion: no dynamics to resolve
  const int hold = s.addGroup();
  for (int n = 0; n < m.nodes(); ++n) {
    const double y = m.coord(n, 1) - sp.axisY, z = m.coord(n, 2), r = std::hypot(y, z);
    const bool core = r <= sp.radius * (1 + 1e-9) && !copy[n];
    for (int i = 0; i < 3; ++i) {
      if (!core) {
        s.addDof(hold, n, i);
        continue;
      }
      const int g = s.addGroup();
      s.addDof(g, n, i);
      const double vi = modeI ? (i == 0 ? 0.0 : -v * (i == 1 ? y : z) / sp.radius) : (i == 0 ? v : 0.0);
      s.setGroupVelocity(g, vi);  // mode I: the core shrinks, the sleeve opens at v
    }
  }
  const auto l = sleeveLaw();
  const double df = modeI ? l.deltaF() : 2 * l.G2() / l.sc();
  s.advanceTo(1.5 * df / v);
  area = 0;
  for (int p = 0; p < s.cohesive()->pairs(); ++p) area += s.cohesive()->tributaryLength(p);
  open = s.cohesive()->fullyDamaged();
  pairs = s.cohesive()->pairs();
  return s.energies().cohesiveDissipated;
}

}  // namespace

TEST(SleeveMesh, FillsTheBlockAndTheSleeveCarriesTheCylinderArea) {
  const auto sp = smallSpec(2.0e-3);
  SleeveMesh sm = sleeveBlock(sp);
  const Mesh& m = sm.mesh;
  ExplicitSolver s(m, {Material::fromSpec(linearSpec(1e6))});
  // every hex has a positive volume (the solver refuses others) and they tile the block
  const double V = sp.width * sp.height * sp.xs.back();
  EXPECT_NEAR(s.physicalMass() / 1000.0 / V, 1.0, 1e-12);
  // split stations x = 0 .. 2 mm (5), 16 nodes around each
  EXPECT_EQ(static_cast<int>(sm.pairs.size()), 5 * 16);
  EXPECT_EQ(static_cast<int>(sm.quads.size()), 5 * 16);  // 4 segments split + the one closing on x = 2.5 mm
  auto ci = CohesiveInterface::fromQuads(m, sm.pairs, {sleeveLaw()}, sm.quads, sm.quadNormals, Eigen::Vector3d::UnitX());
  double A = 0;
  for (int p = 0; p < ci.pairs(); ++p) A += ci.tributaryLength(p);
  // the pairs carry the polygon's area over the split depth plus half the closing segment (nodal
  // integration: the unsplit closing station keeps its half)
  const double expect = polygonPerimeter(sp) * (2.0e-3 + 0.5 * 0.5e-3);
  EXPECT_NEAR(A / expect, 1.0, 1e-12);
  // copies only in the outer elements: no element holds both a pair's original and its copy
  std::vector<int> copyOf(m.nodes(), -1);
  for (auto [a, b] : sm.pairs) copyOf[b] = a;
  for (int e = 0; e < m.elements(); ++e)
    for (int i = 0; i < 8; ++i)
      for (int j = 0; j < 8; ++j) EXPECT_NE(copyOf[m.conn[8 * e + i]], m.conn[8 * e + j]);
}

TEST(SleeveMesh, BadInputIsRefused) {
  auto sp = smallSpec(2e-3);
  sp.radius = 4.5e-3;  // does not fit: 4 mm to the nearest face
  EXPECT_THROW(sleeveBlock(sp), Error);
  sp = smallSpec(2e-3);
  sp.radius = 0;
  EXPECT_THROW(sleeveBlock(sp), Error);
  sp = smallSpec(2e-3);
  sp.xs = {0.0, 1e-3, 1e-3};
  EXPECT_THROW(sleeveBlock(sp), Error);
  sp = smallSpec(-1e-3);  // no station within the sleeve
  EXPECT_THROW(sleeveBlock(sp), Error);
  sp = smallSpec(2e-3);
  SleeveMesh sm = sleeveBlock(sp);
  auto q = sm.quads;
  q[0][0] = sm.pairs[0].first;  // a core-side node in a sleeve quad
  EXPECT_THROW(CohesiveInterface::fromQuads(sm.mesh, sm.pairs, {sleeveLaw()}, q, sm.quadNormals, Eigen::Vector3d::UnitX()),
               Error);
}

TEST(CohesiveSleeve, CorePulledOutAxiallyDissipatesGIIcTimesSleeveArea) {
  double A = 0;
  int open = 0, pairs = 0;
  const double D = kinematicSeparation(false, A, open, pairs);
  std::printf("mode II pull-out: D = %.6g J, G_IIc A = %.6g J, open %d of %d\n", D, sleeveLaw().G2() * A, open, pairs);
  EXPECT_EQ(open, pairs);
  // every pair follows the same pure-shear path to full damage: the closed-form dissipation is exact
  EXPECT_NEAR(D / (sleeveLaw().G2() * A), 1.0, 1e-9);
}

TEST(CohesiveSleeve, CoreShrunkRadiallyDissipatesGIcTimesSleeveArea) {
  double A = 0;
  int open = 0, pairs = 0;
  const double D = kinematicSeparation(true, A, open, pairs);
  std::printf("mode I radial opening: D = %.6g J, G_Ic A = %.6g J, open %d of %d\n", D, sleeveLaw().energy * A, open,
              pairs);
  EXPECT_EQ(open, pairs);
  // the per-pair frame from the curved quads is radial: pure mode I (a shear part would add G_II)
  EXPECT_NEAR(D / (sleeveLaw().energy * A), 1.0, 1e-6);
}
