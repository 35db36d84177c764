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
#include "needlesim/engines/memory_sink.hpp"
#include "engine_tables.hpp"
#include "needlesim/scenario/reader.hpp"

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

namespace {

// Seed 001's needle into a small muscle block with the sleeve seam at muscle toughness
// (examples/cohesive/seed001_biopsy_sleeve.yaml, smaller and shorter).
std::string sleeveYaml(const std::string& depth, const std::string& extra = "") {
  return R"(name: sleeve_insertion
tissue:
  block: {length: 4 mm, width: 6 mm, height: 6 mm}
  material: {law: neo-hookean, C10: 3.6 kPa, nu: 0.495, density: 1060 kg/m^3}
  friction: {coefficient: 0.3}
needle: {outer_diameter: 2.77 mm, inner_diameter: 2.16 mm, length: 50 mm, bevel_angle: 12 deg, tip: bevel}
insertion:
  entry_angle: 90 deg
  start_depth: -0.5 mm
  profile:
    - insert: {to: )" + depth + R"(, speed: 5 mm/s}
model:
  engine: explicit
  explicit:
    dimension: 3d
    element_size: 0.5 mm
    max_element_size: 2 mm
    mass_scaling: 100
    threads: 1
    cohesive: {enable: true, seam: sleeve, fracture_energy: 550 J/m^2, strength: 5.5 MPa, stiffness: 2.75e11 N/m^3)" +
         extra + R"(}
output: {interval: 20 ms}
)";
}

}  // namespace

TEST(CohesiveSleeveInsertion, LongCoreEntersTheBoreAndDissipationIsGcTimesCutSleeve) {
  const double Gc = 550, R = 1.385e-3, ri = 1.08e-3, rs = 0.5 * (R + ri), d = 2.5e-3, h = 0.5e-3;
  MemorySink r = runInMemory(scenario::readText(sleeveYaml("2.5 mm"), "<sleeve>"));
  auto v = [&](const char* k) { return r.results.at(k).value; };
  const double A = v("cracked_area"), Ap = v("process_zone_area"), D = v("cohesive_dissipation");
  // the sleeve cut by the wall: at azimuth theta the edge (bevel plane at r_s) lies s_e(theta) behind the
  // sharp point, and a pair fails once the ramp has opened it by delta_f = 2 G_c / t_c, Delta_f =
  // delta_f / (2 tan 30 deg) behind the edge: cut length L(theta) = max(0, d + s_e(theta) - Delta_f)
  needle::NeedleShape sh;
  sh.radius = R;
  sh.innerRadius = ri;
  sh.tipAngle = 12 * M_PI / 180;
  sh.tip = TipType::Bevel;
  const double dF = 2 * Gc / 5.5e6 / (2 * std::tan(needle::kLipRampAngle));
  double Ageo = 0, arc = 0;
  const int nth = 3600;
  for (int i = 0; i < nth; ++i) {
    const double th = 2 * M_PI * (i + 0.5) / nth, L = std::max(0.0, d + sleeveEdge(sh, rs, std::cos(th)) - dF);
    Ageo += rs * 2 * M_PI / nth * L;
    if (L > 0) arc += rs * 2 * M_PI / nth;
  }
  std::printf("sleeve insertion to %.1f mm: cracked %.4g mm^2 (geometric %.4g, cut arc %.3g mm), process zone %.3g mm^2, "
              "D = %.4g J, G_c A = %.4g J, core in bore %.3f, needle balance %.3g, ke/ie %.3g, peak force %.3g N\n",
              d * 1e3, A * 1e6, Ageo * 1e6, arc * 1e3, Ap * 1e6, D, Gc * A, v("sleeve_core_in_bore"),
              v("needle_energy_balance_error"), v("kinetic_internal_ratio_max"), v("peak_force"));
  // the core side of every pair the wall passed lies in the bore, the outer side outside the wall
  EXPECT_EQ(v("sleeve_core_in_bore"), 1.0);
  // exact bounds: the failed pairs dissipated G_c each, the process zone less
  EXPECT_GE(D, Gc * A * (1 - 1e-9));
  EXPECT_LE(D, Gc * (A + Ap) * (1 + 1e-9));
  // nodal pairs: each column of the cut arc is cracked to the nearest station (+- h/2), and the arc's two
  // ends round to the nearest column of pairs (a chord of 2 pi r_s / 16 by the cut length there, <= h)
  const double chord = 2 * M_PI * rs / 16;
  EXPECT_NEAR(A, Ageo, 0.5 * h * arc + 2 * chord * h);
  EXPECT_GT(A, 0.5 * Ageo);
  // the needle's work goes into the cut, friction, the tissue and the contact springs
  // measured 4.6 % (2.0 % with the softer lip contact, which instead let the entry elements chatter): the
  // penalty energy is a state function only up to the change of k with the step (docs/models/cohesive.md)
  EXPECT_LT(v("needle_energy_balance_error"), 0.08);
  EXPECT_LT(v("kinetic_internal_ratio_max"), 0.2);
}

TEST(CohesiveSleeveInsertion, LongFullCircumferenceCutsAtGcTimesSleevePerimeter) {
  // Seed 001's 12 deg bevel brings the whole circumference to the edge only beyond (R + r_s) / tan 12 deg =
  // 12.3 mm; a 45 deg bevel on the same tube does so at (R + r_s) / tan 45 deg + Delta_f = 2.8 mm, so a short
  // run reaches the steady cut of the examples' deep runs: the force G_c x 2 pi r_s (seed 001 Fig 12's ~4 N).
  std::string y = sleeveYaml("4 mm");
  auto sub = [&](const std::string& a, const std::string& b) { y.replace(y.find(a), a.size(), b); };
  sub("length: 4 mm", "length: 5 mm");
  sub("bevel_angle: 12 deg", "bevel_angle: 45 deg");
  sub("speed: 5 mm/s", "speed: 10 mm/s");
  sub("interval: 20 ms", "interval: 10 ms");
  MemorySink r = runInMemory(scenario::readText(y, "<sleeve45>"));
  const double Gc = 550, R = 1.385e-3, ri = 1.08e-3, rs = 0.5 * (R + ri);
  const double dF = 2 * Gc / 5.5e6 / (2 * std::tan(needle::kLipRampAngle)), dFull = (R + rs) + dF;
  const auto depth = explicit_test::column(r, "energy", "depth"), W = explicit_test::column(r, "energy", "needle_work"),
             D = explicit_test::column(r, "seam", "cohesive_dissipation");
  auto rate = [&](const std::vector<double>& e, double a, double b) {  // d e / d depth between the samples at a, b
    std::size_t i = 0, j = 0;
    while (i + 1 < depth.size() && depth[i] < a - 1e-9) ++i;
    while (j + 1 < depth.size() && depth[j] < b - 1e-9) ++j;
    return (e[j] - e[i]) / (depth[j] - depth[i]);
  };
  // steady window [3, 4] mm, past dFull = 2.79 mm and two stations (2h) long: each of the 16 columns of
  // pairs fails once per station, so dD/dx = G_c x the sleeve's chord polygon (tributary areas) exactly,
  // up to the process zone's change between the window's ends
  const double poly = 2 * 16 * rs * std::sin(M_PI / 16), Fss = Gc * 2 * M_PI * rs;
  const double dD = rate(D, 3e-3, 4e-3), dW = rate(W, 3e-3, 4e-3), dDearly = rate(D, 1e-3, 2e-3);
  std::printf("45 deg sleeve: full cut from %.2f mm; dD/dx over 3-4 mm %.4g N (G_c x polygon %.4g N), dW/dx %.4g N "
              "(G_c 2 pi r_s %.4g N), dD/dx over 1-2 mm %.4g N, needle balance %.3g, ke/ie %.3g\n",
              dFull * 1e3, dD, Gc * poly, dW, Fss, dDearly, r.results.at("needle_energy_balance_error").value,
              r.results.at("kinetic_internal_ratio_max").value);
  EXPECT_NEAR(dD / (Gc * poly), 1.0, 0.02);
  // the needle's mean force: the cut plus the outer wall's friction (measured +1.4 %) and the chord polygon
  // (-0.64 %): within 3 % of G_c 2 pi r_s
  EXPECT_NEAR(dW / Fss, 1.0, 0.03);
  EXPECT_GE(dW, dD);
  // before the full cut only part of the circumference is at the edge
  EXPECT_LT(dDearly, 0.85 * Gc * poly);
  EXPECT_LT(r.results.at("needle_energy_balance_error").value, 0.02);
}

TEST(CohesiveSleeveInsertion, BadInputIsRefused) {
  // a sleeve radius outside the needle wall
  EXPECT_THROW(scenario::readText(sleeveYaml("1 mm", ", sleeve_radius: 1.5 mm"), "<bad>"), Error);
  // a solid needle has no bore
  std::string solid = sleeveYaml("1 mm");
  solid.replace(solid.find("inner_diameter: 2.16 mm"), 23, "inner_diameter: 0 mm");
  EXPECT_THROW(scenario::readText(solid, "<bad>"), Error);
  // 2D
  std::string flat = sleeveYaml("1 mm");
  flat.replace(flat.find("dimension: 3d"), 13, "dimension: 2d");
  EXPECT_THROW(scenario::readText(flat, "<bad>"), Error);
  // an unknown seam
  std::string seam = sleeveYaml("1 mm");
  seam.replace(seam.find("seam: sleeve"), 12, "seam: tube");
  EXPECT_THROW(scenario::readText(seam, "<bad>"), Error);
}
