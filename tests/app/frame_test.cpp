// One scenario through every engine that accepts it (docs/models/frame.md): the
// engines share one frame, so they must agree on the physics' signs.
//  - A bevel tip is pushed away from the side its face looks to (seed 002 section 3,
//    seed 003 section 3.4): at bevel_orientation 0 the face looks to +lateral, so the
//    tissue's lateral force on the needle is < 0 (rigid needles: mpm, explicit; the
//    flexible realtime2d needle as well) and a flexible needle bends to -lateral; at
//    180 deg both change sign. The steering paths curve to -y.
//  - An oblique needle (entry_angle 70 deg) goes towards +y as it goes deeper: every
//    engine puts its tip at y > entry_offset.
// The block, needle and motion are one text; only model.engine changes between runs.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "needlesim/engines/memory_sink.hpp"
#include "needlesim/scenario/reader.hpp"

using namespace needlesim;

namespace {

// 12 x 10 x 6 mm soft gel, a 2 mm 45 deg needle pushed 4 mm in: seconds in every engine.
std::string scenario(const std::string& engine, const std::string& insertion, const std::string& tip) {
  return R"(
name: frame
tissue:
  block: {length: 12 mm, width: 10 mm, height: 6 mm}
  material: {law: neo-hookean, C10: 3.6 kPa, nu: 0.45, density: 1000 kg/m^3}
  puncture: {force: 0.02 N}
  cutting: {force: 0.05 N}
  friction: {C_p: 1 N/m, b_p: 10 N s/m^2, coefficient: 0.1}
needle: {outer_diameter: 2 mm, length: 40 mm, bevel_angle: 45 deg, tip: )" +
         tip + R"(, youngs_modulus: 200 GPa}
insertion:
)" + insertion +
         R"(  start_depth: -0.5 mm
  profile:
    - insert: {to: 4 mm, speed: 10 mm/s}
model:
  engine: )" +
         engine + R"(
  time_step: 1 ms
  realtime2d: {nodes_depth: 13, nodes_lateral: 21, field_interval: 0 s}
  explicit: {dimension: 2d, element: quad4, element_size: 0.5 mm, max_element_size: 2 mm, core_width: 4 mm,
             mass_scaling: 15, tip_friction: 0, pre_cut: false}
  mpm: {grid_spacing: 1 mm, particle_spacing: 0.5 mm, mass_scaling: 1e4, field_interval: 0 s,
        faces: {exit: fixed, y_min: roller, y_max: roller, z_min: roller, z_max: roller}}
  steering: {increment: 0.5 mm}
output: {interval: 10 ms}
)";
}

MemorySink run(const std::string& engine, const std::string& insertion, const std::string& tip = "bevel") {
  return runInMemory(scenario::readText(scenario(engine, insertion, tip), "<frame " + engine + ">"));
}

// Mean of a forces.csv column over the rows of the last half of the insertion depth.
double lateMean(const MemorySink& m, const std::string& column) {
  const auto& t = m.tables.at("forces");
  const auto depth = t.column("depth"), v = t.column(column);
  double s = 0.0;
  int n = 0;
  for (std::size_t i = 0; i < v.size(); ++i)
    if (depth[i] >= 2e-3) s += v[i], ++n;
  return n > 0 ? s / n : NAN;
}

double lastTipY(const MemorySink& m) {
  const char* table = m.tables.count("forces") ? "forces" : "tip_path";
  return m.tables.at(table).column("tip_y").back();
}

bool hasColumn(const MemorySink& m, const std::string& table, const std::string& column) {
  for (const auto& c : m.tables.at(table).columns())
    if (c.name == column) return true;
  return false;
}

const char* kNormal = "  entry_angle: 90 deg\n";

}  // namespace

TEST(OneFrame, BevelPushesEveryNeedleToTheSameSide) {
  for (const char* engine : {"realtime2d", "explicit", "mpm"}) {
    const MemorySink zero = run(engine, std::string(kNormal) + "  bevel_orientation: 0 deg\n");
    const MemorySink half = run(engine, std::string(kNormal) + "  bevel_orientation: 180 deg\n");
    const double f0 = lateMean(zero, "force_lateral"), f180 = lateMean(half, "force_lateral");
    EXPECT_LT(f0, 0.0) << engine;
    EXPECT_GT(f180, 0.0) << engine;
    // mirror images of one another in a block symmetric about the path
    EXPECT_NEAR(f0, -f180, 0.05 * std::abs(f0)) << engine;
    if (hasColumn(zero, "forces", "tip_deflection")) {  // a flexible needle
      EXPECT_LT(zero.tables.at("forces").column("tip_deflection").back(), 0.0) << engine;
      EXPECT_GT(half.tables.at("forces").column("tip_deflection").back(), 0.0) << engine;
    }
  }
  EXPECT_LT(run("kinematic", kNormal).tables.at("tip_path").column("tip_y").back(), 0.0);
}

TEST(OneFrame, ObliqueNeedleGoesTowardsPlusYInEveryEngine) {
  const std::string oblique = "  entry_angle: 70 deg\n  entry_offset: 1 mm\n";
  for (const char* engine : {"lumped", "realtime2d", "explicit", "mpm"}) {
    const MemorySink m = run(engine, oblique, "conical");
    // the tip at 4 mm along an axis 20 deg off the face normal: y = 1 mm + 4 mm sin 20 deg
    EXPECT_NEAR(lastTipY(m), 1e-3 + 4e-3 * std::sin(20.0 * M_PI / 180.0), 0.1e-3) << engine;
    EXPECT_GT(lateMean(m, "force_total"), 0.0) << engine;
  }
  // a straight path of the kinematic model: conical tip, no curvature
  EXPECT_NEAR(lastTipY(run("kinematic", oblique, "conical")), 1e-3 + 4e-3 * std::sin(20.0 * M_PI / 180.0), 1e-9);
}
