// Energy bookkeeping of the needle contact (solver.cpp: needle work, Coulomb friction
// dissipation, penalty energy; docs/models/cohesive.md "Energy balance") and the
// mesh objectivity of the insertion's cohesive dissipation (docs/validation/cohesive.md
// "Verification").
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "needlesim/engines/memory_sink.hpp"
#include "needlesim/scenario/reader.hpp"

using namespace needlesim;

namespace {
std::string yaml2d(const std::string& precut, double mu, double h, double depth, bool coh, double Gc = 10.0,
                   const std::string& extra = "") {
  return std::string(R"(
name: energy_2d
tissue:
  block: {length: 10 mm, width: 10 mm, height: 10 mm}
  material: {law: neo-hookean, C10: 3.6 kPa, nu: 0.45, density: 1000 kg/m^3}
  friction: {coefficient: )") + std::to_string(mu) + R"(}
  interaction: {toughness: )" + std::to_string(Gc) + R"( J/m^2}
needle: {outer_diameter: 2 mm, length: 30 mm, bevel_angle: 45 deg, tip: bevel, youngs_modulus: 200 GPa}
insertion:
  entry_angle: 90 deg
  start_depth: -0.5 mm
  profile:
    - insert: {to: )" + std::to_string(depth * 1e3) + R"( mm, speed: 10 mm/s}
model:
  engine: explicit
  explicit:
    dimension: 2d
    element: quad4
    element_size: )" + std::to_string(h * 1e3) + R"( mm
    max_element_size: 2 mm
    core_width: 4 mm
    mass_scaling: 15
    tip_friction: 0
)" + extra + R"(    pre_cut: )" + precut + R"(
    cohesive: {enable: )" + (coh ? "true" : "false") + R"(, strength: 20 kPa}
output: {interval: 10 ms}
)";
}
double res(const MemorySink& m, const char* k) { return m.results.at(k).value; }
}  // namespace

// Plain needle contact (no seam: the needle indents the block) with wall friction 0.3: the work the
// moving needle does equals kinetic + internal + friction dissipation + penalty energy within 2 %.
TEST(NeedleEnergy, IndentationWithFrictionBalancesNeedleWork) {
  MemorySink r = runInMemory(scenario::readText(yaml2d("false", 0.3, 0.5e-3, 1.2e-3, false), "<indent>"));
  const double W = res(r, "needle_work"), Df = res(r, "friction_dissipation"), Ep = res(r, "penalty_energy");
  std::printf("indentation: needle work %.4g J, friction dissipation %.4g J, penalty energy %.4g J, viscous %.3g J, "
              "needle balance error %.3g, body balance %.2g\n",
              W, Df, Ep, res(r, "viscous_dissipation"), res(r, "needle_energy_balance_error"),
              res(r, "energy_balance_error"));
  EXPECT_GT(W, 0.0);
  EXPECT_GT(Df, 0.02 * W);  // the shaft slides against the bevel-side wall under friction
  EXPECT_GT(Ep, 0.0);
  EXPECT_LT(res(r, "needle_energy_balance_error"), 0.02);
  EXPECT_LT(res(r, "energy_balance_error"), 1e-9);
}

// Whole 2D insertion with the cohesive seam cutting and wall friction 0.3, with the conservative penalty
// (fixed_contact_stiffness, contact_penalty 0.4): needle work = kinetic + internal (strain, hourglass,
// viscous) + cohesive (stored + dissipated) + friction dissipation + penalty energy within 2 %.
TEST(NeedleEnergy, CohesiveInsertionWithFrictionBalancesNeedleWork) {
  const std::string fixedK = "    contact_penalty: 0.4\n    fixed_contact_stiffness: true\n";
  MemorySink r = runInMemory(scenario::readText(yaml2d("true", 0.3, 0.5e-3, 4e-3, true, 10.0, fixedK), "<coh>"));
  const double W = res(r, "needle_work");
  std::printf("cohesive insertion (fixed k): needle work %.4g J = cohesive D %.4g + stored %.3g + friction %.4g + "
              "penalty %.3g + viscous %.3g + strain, kinetic ...; needle balance error %.3g, body balance %.2g, "
              "cracked %.3g mm^2\n",
              W, res(r, "cohesive_dissipation"), res(r, "cohesive_stored"), res(r, "friction_dissipation"),
              res(r, "penalty_energy"), res(r, "viscous_dissipation"), res(r, "needle_energy_balance_error"),
              res(r, "energy_balance_error"), res(r, "cracked_area") * 1e6);
  EXPECT_GT(res(r, "cracked_area"), 4e-6);               // it cut: > 2 mm of the 4 mm path x 2 mm
  EXPECT_GT(res(r, "friction_dissipation"), 0.1 * W);    // the shaft slides under friction
  EXPECT_GT(res(r, "cohesive_dissipation"), 0.3 * W);    // cutting takes a good part of the work
  EXPECT_LT(res(r, "needle_energy_balance_error"), 0.02);
  EXPECT_LT(res(r, "energy_balance_error"), 1e-9);
}

// The same insertion on the default contact settings (penalty 10 implicit, seam lips 0.3 explicit, each
// node's stiffness kept over its contact episode, solver.cpp episodeStiffness): within 2 % too. With k
// following the shrinking stable step the stored 1/2 k g^2 grew without work and the balance was 18.8 %
// off (fails with the per-episode stiffness taken out).
TEST(NeedleEnergy, CohesiveInsertionOnDefaultsBalancesNeedleWork) {
  MemorySink r = runInMemory(scenario::readText(yaml2d("true", 0.3, 0.5e-3, 4e-3, true), "<coh>"));
  const double W = res(r, "needle_work");
  std::printf("cohesive insertion (defaults): needle work %.4g J = cohesive D %.4g + stored %.3g + friction %.4g + "
              "penalty %.3g + viscous %.3g + strain, kinetic ...; needle balance error %.3g, cracked %.3g mm^2\n",
              W, res(r, "cohesive_dissipation"), res(r, "cohesive_stored"), res(r, "friction_dissipation"),
              res(r, "penalty_energy"), res(r, "viscous_dissipation"), res(r, "needle_energy_balance_error"),
              res(r, "cracked_area") * 1e6);
  EXPECT_GT(res(r, "cracked_area"), 4e-6);
  EXPECT_GT(res(r, "friction_dissipation"), 0.1 * W);
  EXPECT_GT(res(r, "cohesive_dissipation"), 0.3 * W);
  EXPECT_LT(res(r, "needle_energy_balance_error"), 0.02);
  EXPECT_LT(res(r, "energy_balance_error"), 1e-9);
}

// A finer mesh and a tougher-to-balance law (G_c = 2 J/m^2, delta_f = 0.2 mm, h = 0.125 mm) on the defaults:
// the lips of fully damaged pairs stay on the wedge rule (solver.cpp). With the switch to queryNeedle's lip
// side rules at d = 1 a wall-side lip released above the point's line by the chisel was later found inside
// the bevel sliver and sent out through the wall (a jump in depth): 8.4 % off; with the wedge kept, 0.26 %.
TEST(NeedleEnergy, FineMeshCutBalancesNeedleWork) {
  MemorySink r = runInMemory(scenario::readText(yaml2d("true", 0.3, 0.125e-3, 4e-3, true, 2.0), "<fine>"));
  std::printf("fine cut (h 0.125 mm, G_c 2 J/m^2): needle work %.4g J, cohesive D %.4g J, friction %.4g J, needle balance "
              "error %.3g, front %.3f mm behind the point\n",
              res(r, "needle_work"), res(r, "cohesive_dissipation"), res(r, "friction_dissipation"),
              res(r, "needle_energy_balance_error"), (4e-3 - res(r, "crack_tip")) * 1e3);
  EXPECT_GT(res(r, "cracked_area"), 6e-6);  // > 3 mm of the 4 mm path x 2 mm
  EXPECT_LT(res(r, "needle_energy_balance_error"), 0.02);
  EXPECT_LT(res(r, "energy_balance_error"), 1e-9);
}

// Mesh objectivity of the insertion's dissipation: element 0.5 and 0.25 mm, G_c = 2 J/m^2 (delta_f =
// 0.2 mm: the finer mesh stops on the lip contact near 2 mm with the 1 mm delta_f of the other tests),
// 1.9 mm of insertion. Per unit cracked area both dissipate G_c (plus the process zone's share); the
// fully damaged front trails the sharp point by about 2 elements (the nodal wedge opens a pair once the
// bevel has lifted its upper lip by delta_f), so the dissipation at a given depth converges with h.
TEST(CohesiveInsertion, MeshObjectivityOfDissipation) {
  const double depth = 1.9e-3, Gc = 2.0;
  MemorySink c = runInMemory(scenario::readText(yaml2d("true", 0.3, 0.5e-3, depth, true, Gc), "<coarse>"));
  MemorySink f = runInMemory(scenario::readText(yaml2d("true", 0.3, 0.25e-3, depth, true, Gc), "<fine>"));
  const double Dc = res(c, "cohesive_dissipation"), Df = res(f, "cohesive_dissipation");
  const double Ac = res(c, "cracked_area"), Af = res(f, "cracked_area");
  const double lagC = depth - res(c, "crack_tip"), lagF = depth - res(f, "crack_tip");
  std::printf("mesh objectivity: h 0.5 mm: D %.5g J, cracked %.4g mm^2, D/A %.4g J/m^2, front %.3f mm behind the point; "
              "h 0.25 mm: D %.5g J, cracked %.4g mm^2, D/A %.4g J/m^2, front %.3f mm behind; D fine/coarse %.4f; "
              "needle balance %.3g / %.3g\n",
              Dc, Ac * 1e6, Dc / Ac, lagC * 1e3, Df, Af * 1e6, Df / Af, lagF * 1e3, Df / Dc,
              res(c, "needle_energy_balance_error"), res(f, "needle_energy_balance_error"));
  EXPECT_NEAR(Dc / Ac, Gc, 0.1 * Gc);
  EXPECT_NEAR(Df / Af, Gc, 0.1 * Gc);
  EXPECT_LT(lagC, 2.5 * 0.5e-3);
  EXPECT_LT(lagF, 2.5 * 0.25e-3);
  // the finer mesh's extra dissipation is bounded by the shorter lag: D_f - D_c <= G_c (lag_c - lag_f) x 2 mm
  EXPECT_GT(Df, Dc);
  EXPECT_LE(Df - Dc, 1.05 * Gc * (lagC - lagF) * 2e-3);
}
