// realtime2d in the shared insertion frame (needle/insertion_frame.hpp): the tissue
// pushes a bevel tip towards -bevelSide (seed 003 section 3.4), so at bevel_orientation
// 0 the tip load, the lateral force and the tip deflection are < 0 along `lateral`, at
// 180 deg > 0; an oblique needle (entry_angle < 90 deg) goes towards +y as it goes deeper.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

#include <fmt/format.h>

#include "needlesim/engines/memory_sink.hpp"
#include "needlesim/engines/realtime2d/session.hpp"
#include "needlesim/scenario/reader.hpp"

using namespace needlesim;

namespace {
constexpr double kDeg = std::numbers::pi / 180.0;

// 20 mm at 10 mm/s into a 40 x 40 mm gelatin section on a coarse mesh.
Scenario insertion(double entryAngleDeg, double offsetMm, double bevelDeg) {
  const std::string y = fmt::format(R"(name: frame
tissue:
  block: {{length: 40 mm, width: 40 mm, height: 20 mm}}
  material: gelatin_10wt
  puncture: {{force: 0.02 N}}
  cutting: {{force: 0.04335 N}}
  friction: {{C_p: 3.791 N/m, b_p: 285.053 N s/m^2, static_band: 0.1 mm/s}}
needle: {{outer_diameter: 18 G, length: 100 mm, bevel_angle: 30 deg, tip: bevel}}
insertion:
  entry_angle: {} deg
  entry_offset: {} mm
  bevel_orientation: {} deg
  start_depth: -0.5 mm
  profile:
    - insert: {{to: 20 mm, speed: 10 mm/s}}
model:
  engine: realtime2d
  time_step: 1 ms
  realtime2d: {{nodes_depth: 11, nodes_lateral: 15, field_interval: 0 s}}
output: {{interval: 10 ms}}
)",
                                    entryAngleDeg, offsetMm, bevelDeg);
  return scenario::readText(y, "<frame>");
}

struct Final {
  double lateral, deflection, tip_x, tip_y, depth;
};

Final runFinal(const Scenario& sc) {
  const MemorySink out = runInMemory(sc);
  const auto& f = out.tables.at("forces");
  const std::size_t n = f.rows() - 1;
  auto at = [&](const char* c) { return f.column(c)[n]; };
  return {at("force_lateral"), at("tip_deflection"), at("tip_x"), at("tip_y"), at("depth")};
}
}  // namespace

TEST(Realtime2dFrame, EngineBevelPushesTheTipTowardsMinusBevelSide) {
  const Final b0 = runFinal(insertion(90, 0, 0));
  EXPECT_LT(b0.deflection, -1e-5);
  EXPECT_LT(b0.lateral, 0.0);
  EXPECT_NEAR(b0.tip_y, b0.deflection, 1e-12);  // lateral = +y at 90 deg, entry at the centre
  const Final b180 = runFinal(insertion(90, 0, 180));
  EXPECT_GT(b180.deflection, 1e-5);
  EXPECT_GT(b180.lateral, 0.0);
  // The mesh is symmetric about the path line: the flipped bevel mirrors the run.
  EXPECT_NEAR(b180.deflection, -b0.deflection, 1e-9 * std::abs(b0.deflection));
}

// tip = entry + depth axial + deflection lateral, axial = (sin th, cos th),
// lateral = (-cos th, sin th), in the centred tissue frame.
TEST(Realtime2dFrame, EngineObliqueInsertionGoesTowardsPlusY) {
  const double th = 70 * kDeg, offset = 5e-3;
  const Final f = runFinal(insertion(70, offset * 1e3, 0));
  EXPECT_GT(f.tip_y, offset + 0.5 * f.depth * std::cos(th));
  EXPECT_NEAR(f.tip_x, f.depth * std::sin(th) - f.deflection * std::cos(th), 1e-12);
  EXPECT_NEAR(f.tip_y, offset + f.depth * std::cos(th) + f.deflection * std::sin(th), 1e-12);
}

namespace {
realtime2d::StepResult sessionInsertion(const InsertionSpec& ins, double roll) {
  realtime2d::SessionConfig c = realtime2d::thesisGelatinConfig(11, 15);
  c.tissue.mesh.length = c.tissue.mesh.width = 0.04;
  c.puncture_force = 0.02;
  c.frame = needle::InsertionFrame::fromInsertion(ins);
  realtime2d::Session s(c);
  for (int n = 1; n <= 2000; ++n) s.step(s.poseAtDepth(-5e-4 + 1e-2 * n * c.dt, 0.0, 0.0, roll), c.dt);
  return s.last();
}
}  // namespace

TEST(Realtime2dFrame, SessionBevelSignFollowsTheFrame) {
  InsertionSpec ins;
  ins.entry_angle = 0.5 * std::numbers::pi;
  const auto b0 = sessionInsertion(ins, 0.0);
  EXPECT_LT(b0.tip_load, 0.0);
  EXPECT_LT(b0.lateral_force, 0.0);
  EXPECT_LT(b0.tip_deflection, -1e-5);
  const auto rolled = sessionInsertion(ins, std::numbers::pi);  // turned by 180 deg
  EXPECT_GT(rolled.tip_deflection, 1e-5);
  ins.bevel_orientation = std::numbers::pi;  // the same through the frame's bevel orientation
  const auto b180 = sessionInsertion(ins, 0.0);
  EXPECT_EQ(b180.tip_deflection, rolled.tip_deflection);
  EXPECT_GT(b180.lateral_force, 0.0);
}

TEST(Realtime2dFrame, SessionObliqueInsertionInTheCentredFrame) {
  InsertionSpec ins;
  ins.entry_angle = 70 * kDeg;
  ins.entry_offset = 5e-3;
  const auto r = sessionInsertion(ins, 0.0);
  const double th = ins.entry_angle;
  EXPECT_GT(r.tip_position.y(), ins.entry_offset + 0.5 * r.depth * std::cos(th));
  EXPECT_NEAR(r.tip_position.x(), r.depth * std::sin(th) - r.tip_deflection * std::cos(th), 1e-12);
  EXPECT_NEAR(r.tip_position.y(), ins.entry_offset + r.depth * std::cos(th) + r.tip_deflection * std::sin(th), 1e-12);
}
