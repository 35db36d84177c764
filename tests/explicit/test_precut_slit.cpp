// The 3D pre-cut slit through the bevel's sharp point (docs/models/explicit.md "Pre-cut slit (3D)"):
// the needle's load does not depend on which nodes happen to lie inside it, so the axial force converges
// with the core element size; the bevel lifts only the bevel-side lip, so the needle is pushed away from
// its face; a mesh on which the needle touches no node is refused instead of giving 0 N.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "needlesim/core/error.hpp"
#include "needlesim/engines/memory_sink.hpp"
#include "needlesim/scenario/reader.hpp"

using namespace needlesim;

namespace {

// The reference gel and needle (examples/agreement/explicit_3d.yaml) in a small block, 5 mm deep.
std::string slitYaml(const std::string& size, const std::string& extra = "", const std::string& depth = "5 mm") {
  return R"(
name: slit_convergence
tissue:
  block: {length: 10 mm, width: 8 mm, height: 8 mm}
  material: {law: neo-hookean, C10: 3.5 kPa, nu: 0.45, density: 1000 kg/m^3}
  friction: {coefficient: 0.25}
needle: {outer_diameter: 1.27 mm, length: 30 mm, bevel_angle: 30 deg, tip: bevel, youngs_modulus: 200 GPa}
insertion:
  entry_angle: 90 deg
  start_depth: -0.5 mm
  profile:
    - insert: {to: )" + depth + R"(, speed: 10 mm/s}
model:
  engine: explicit
  explicit:
    dimension: 3d
    element: hex8
    element_size: )" + size + R"(
    max_element_size: 1.5 mm
    core_width: 3 mm
    mass_scaling: 100
    tip_friction: 0
)" + extra + R"(output: {interval: 10 ms}
)";
}

// Mean of a forces column with the tip between 2 mm and the end of the travel (past the entry).
double meanFrom2mm(const MemorySink& r, const std::string& column) {
  const io::Table& f = r.tables.at("forces");
  const auto d = f.column("depth"), v = f.column(column);
  double sum = 0;
  int n = 0;
  for (std::size_t i = 0; i < d.size(); ++i)
    if (d[i] >= 2e-3) sum += v[i], ++n;
  return n ? sum / n : 0.0;
}

// Mean axial force over the last half millimetre of travel (the node releases make a ripple of one element).
double axialForceNear(const MemorySink& r, double depth) {
  const io::Table& f = r.tables.at("forces");
  const auto d = f.column("depth"), F = f.column("force_total");
  double sum = 0;
  int n = 0;
  for (std::size_t i = 0; i < d.size(); ++i)
    if (d[i] >= depth - 0.5e-3 - 1e-9 && d[i] <= depth + 1e-9) sum += F[i], ++n;
  return n ? sum / n : 0.0;
}

}  // namespace

// Core 0.6 mm (3 elements across the slit) against 0.4 mm (4). A seam felt only through the nodes that
// happen to lie inside the needle (queryNeedle's nearest exit, as through imported meshes) stops on
// penetration at 3.3 mm on this block at 0.6 mm and went 11 / 33 / 94 mN at 20 mm on the reference block at
// 0.7 / 0.5 / 0.35 mm. The slit's lips take the needle's outline at each node: the bevel-side lip's polygon
// inscribed in the upper half of the needle's section holds 80 % of the half disc with 3 elements and 87 %
// with 4 (lip nodes at b = +-R/3, and at 0 and +-R/2), 9 % apart; the limit, 20 %, allows twice that (the
// window's 6 rows also hold the node-release ripple of one element). Measured 29.8 / 31.7 mN over the last
// 0.5 mm (-6 %); docs/models/explicit.md "Pre-cut slit (3D)".
TEST(PrecutSlit3d, LongAxialForceHardlyChangesWithTheCoreElementSize) {
  const MemorySink coarse = runInMemory(scenario::readText(slitYaml("0.6 mm"), "<slit-0.6>"));
  const MemorySink fine = runInMemory(scenario::readText(slitYaml("0.4 mm"), "<slit-0.4>"));
  const double Fc = axialForceNear(coarse, 5e-3), Ff = axialForceNear(fine, 5e-3);
  std::printf("axial force at 4.5-5 mm: core 0.6 mm %.4g mN, 0.4 mm %.4g mN (%+.1f %%)\n", Fc * 1e3, Ff * 1e3,
              100 * (Fc / Ff - 1));
  ASSERT_GT(Ff, 0.0);
  EXPECT_LT(std::abs(Fc / Ff - 1), 0.20);
}

// A bevel cuts at its sharp point: the whole needle lifts the bevel-side lip and none of it the wall-side
// lip, so the tissue pushes the needle away from its face (docs/models/frame.md; every other engine, and
// this one without the slit: OneFrame.BevelPushesEveryNeedleToTheSameSide). A slit through the axis opened
// the wall-side lip further at the tip and gave the opposite sign (+5.4 mN over 2-5 mm on this block).
// Turned by 180 deg the needle, the slit and the mesh are the mirror image: the force changes sign, equal
// to the 5 % of the frame test (the explicit sums run in another order).
TEST(PrecutSlit3d, BevelPushesTheNeedleAwayFromItsFace) {
  const MemorySink zero = runInMemory(scenario::readText(slitYaml("0.6 mm"), "<slit-bevel-0>"));
  std::string half = slitYaml("0.6 mm");
  half.replace(half.find("  start_depth"), 0, "  bevel_orientation: 180 deg\n");
  const MemorySink flipped = runInMemory(scenario::readText(half, "<slit-bevel-180>"));
  const double f0 = meanFrom2mm(zero, "force_lateral"), f180 = meanFrom2mm(flipped, "force_lateral");
  std::printf("lateral force, mean over 2-5 mm: bevel at 0 deg %.4g mN, 180 deg %.4g mN\n", f0 * 1e3, f180 * 1e3);
  EXPECT_LT(f0, 0.0);
  EXPECT_GT(f180, 0.0);
  EXPECT_NEAR(f0, -f180, 0.05 * std::abs(f0));
}

// A core as coarse as the needle's diameter leaves no node on the slit: refused with the field and the size.
TEST(PrecutSlit3d, ACoreAsCoarseAsTheNeedleIsRefused) {
  try {
    runInMemory(scenario::readText(slitYaml("1.5 mm"), "<slit-1.5mm>"));
    FAIL() << "a 1.5 mm core was accepted for a 1.27 mm needle";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("model.explicit.element_size"), std::string::npos) << what;
    EXPECT_NE(what.find("1.27 mm"), std::string::npos) << what;
  }
}

// Without the slit (pre_cut: false) a 1 mm core has no node within 0.635 mm of the axis: the needle passes
// between the nodes. The run stops (SolverError, exit 1) instead of completing with 0 N.
TEST(PrecutSlit3d, ANeedleThatTouchesNoNodeStopsTheRun) {
  const Scenario sc = scenario::readText(slitYaml("1 mm", "    pre_cut: false\n", "3 mm"), "<no-slit-1mm>");
  try {
    runInMemory(sc);
    FAIL() << "a needle touching no node completed";
  } catch (const SolverError& e) {
    EXPECT_NE(std::string(e.what()).find("without touching a tissue node"), std::string::npos) << e.what();
  }
}
