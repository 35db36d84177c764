// realtime3d's force bookkeeping (engines/realtime): the cutting load counted once (seed 003
// eq 3.24), contact lengths that add up when path nodes overtake (eq 3.23 per length), and the
// warning once the linear tissue model no longer holds (realtime/linear_range.hpp).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "needlesim/engines/memory_sink.hpp"
#include "needlesim/engines/realtime3d/realtime3d_engine.hpp"
#include "needlesim/engines/realtime3d/session.hpp"
#include "needlesim/scenario/reader.hpp"

using namespace needlesim;
using namespace needlesim::realtime3d;

namespace {
// A soft neo-Hookean gel (C10 3.5 kPa) and an 18 G needle: graded fine along the path
// (refinement 16), where the shaft drags the entry nodes past deeper ones.
std::string softGel(const std::string& b_p, const std::string& model = "") {
  return R"(
name: soft_gel
tissue:
  block: {length: 30 mm, width: 20 mm, height: 20 mm}
  material: {law: neo-hookean, C10: 3.5 kPa, nu: 0.45, density: 1000 kg/m^3}
  puncture: {force: 0.05 N}
  cutting: {force: 0.04335 N}
  friction: {C_p: 3.791 N/m, b_p: )" + b_p + R"( N s/m^2, static_band: 0.1 mm/s}
needle: {outer_diameter: 18 G, length: 100 mm, bevel_angle: 30 deg}
insertion:
  start_depth: -1 mm
  profile:
    - insert: {to: 20 mm, speed: 3 mm/s}
model:
  engine: realtime3d
  time_step: 1 ms
  realtime3d: {nodes_depth: 31, nodes_lateral: 9, nodes_height: 9, refinement: 16, field_interval: 0 s)" + model + R"(}
output: {interval: 10 ms}
)";
}
}  // namespace

TEST(Realtime3dBookkeeping, WithoutFrictionTheAxialForceIsTheCuttingForceAtEveryDepth) {
  SessionConfig c = gelatinBlockConfig(11, 7, Backend::Direct);
  c.puncture_force = 0.05;
  c.friction.C_p = c.friction.C_n = c.friction.b_p = c.friction.b_n = c.friction.D_p = c.friction.D_n = 0.0;
  Session s(c);
  int cutting = 0, off = 0;
  double worst = 0.0;
  for (int n = 1; n <= 20000; ++n) {  // 59 mm at 3 mm/s, across 7 node spacings
    const auto& r = s.step(s.poseAtDepth(-1e-3 + 3e-3 * n * c.dt), c.dt);
    if (r.phase != Phase::Cutting) continue;
    ++cutting;
    const double e = std::max(std::abs(r.axial_force - c.cutting_force), std::abs(r.friction_force));
    worst = std::max(worst, e);
    off += e > 1e-12;
  }
  EXPECT_GT(cutting, 15000);
  EXPECT_EQ(off, 0) << "largest difference " << worst << " N";
}

// The shaft's contact lengths add up to the shaft in the tissue at every step, and are never
// negative (the lengths follow the points' current order along the axis; points embedded in the
// tets keep their order unless a tet inverts, so none overtakes here, 0.25 mm apart in a soft gel).
TEST(Realtime3dBookkeeping, ContactLengthsAddUpAndStayNonNegative) {
  const SessionConfig c =
      engines::realtime3dConfig(scenario::readText(softGel("285.053", ", coupling_spacing: 0.25 mm"), "<soft gel>"));
  Session s(c);
  int overtaken = 0;
  for (int n = 1; n <= 7000; ++n) {
    const double depth = -1e-3 + 3e-3 * n * c.dt;
    const auto& r = s.step(s.poseAtDepth(depth), c.dt);
    const auto& sh = s.shaft();
    double sum = 0.0;
    for (int i = 0; i < r.coupled; ++i) {
      EXPECT_GE(sh.contactLength(i), 0.0);
      sum += sh.contactLength(i);
      overtaken += i > 0 && sh.position(i) < sh.position(i - 1);
    }
    if (r.coupled > 0) ASSERT_NEAR(sum, std::min(depth, s.exitDepth()), 1e-12) << depth;
  }
  std::printf("%d overtaken\n", overtaken);
}

// The soft gel strains its path elements far beyond the linear range: one warning, naming the
// depth and the strain; the stiffer quick block stays within it and gets none.
TEST(Realtime3dBookkeeping, LeavingTheLinearRangeIsWarnedOnce) {
  const MemorySink soft = runInMemory(scenario::readText(softGel("285.053"), "<soft gel>"));
  int linear = 0;
  for (const auto& w : soft.warnings) linear += w.find("linear tissue model no longer holds") != std::string::npos;
  EXPECT_EQ(linear, 1);
  const MemorySink quick = runInMemory(scenario::readFile(NEEDLESIM_SOURCE_DIR "/examples/realtime3d/quick_block.yaml"));
  for (const auto& w : quick.warnings) EXPECT_EQ(w.find("linear tissue model"), std::string::npos) << w;
}
