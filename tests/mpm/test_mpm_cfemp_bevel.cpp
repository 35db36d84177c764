// CFEMP particle-to-surface contact (seed 000 eqs 22-24) at the sharp point of
// a bevel needle: which facet's normal acts on a material point just ahead of
// it. docs/models/mpm.md (CFEMP) and docs/validation/mpm.md (local model).
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "needlesim/engines/memory_sink.hpp"
#include "needlesim/engines/mpm/mpm_engine.hpp"
#include "needlesim/engines/mpm/mpm_solver.hpp"
#include "needlesim/scenario/reader.hpp"

using namespace needlesim;
using namespace needlesim::mpm;

namespace {

// One material point at rest, `ahead` m ahead of the sharp point of a 20 G
// bevel needle (20 deg, sharp point at +R y) and `radial` m beyond its radius
// (negative: inside the cylinder's cross-section); the needle moves along +x
// without friction. Returns the needle force of the first step.
RigidForce forceFromOnePoint(double ahead, double radial) {
  constexpr double R = 0.44e-3, dp = 0.4e-3;
  MpmConfig cfg;
  cfg.h = 0.8e-3;
  cfg.origin = Vec3(-4e-3, -4e-3, -4e-3);
  cfg.cells = {10, 10, 10};
  cfg.threads = 1;
  MpmSolver s(cfg);
  MpmMaterial m;
  m.law.kind = materials::LawKind::Linear;
  m.law.E = 30e3;
  m.law.nu = 0.45;
  m.density = 1000;
  s.addMaterial(m);
  const Vec3 centre(ahead, R + radial, 0.0);
  s.addBlock(centre - Vec3::Constant(0.5 * dp), centre + Vec3::Constant(0.5 * dp), dp, 0, 0);
  EXPECT_EQ(s.size(), 1u);
  RigidBody n;
  n.kind = RigidBody::Kind::Needle;
  n.tip = RigidBody::Tip::Bevel;
  n.tipAngle = 20.0 * std::numbers::pi / 180.0;
  n.radius = R;
  n.length = 5e-3;
  n.axis = Vec3::UnitX();
  n.bevelSide = -Vec3::UnitY();  // heel at -R y
  n.point = Vec3(0, R, 0);  // the sharp point; the axis runs through the origin
  n.velocity = Vec3(0.01, 0, 0);
  n.surfaceContact = true;
  const int r = s.addRigid(n);
  s.finalize();
  s.step();
  return s.rigidForce(r);
}

}  // namespace

// A point 0.15 mm ahead of the sharp point and 0.01 mm outside the radius is
// nearest to the sharp point itself (a vertex shared by bevel and wall facets),
// within the eq 22 gap d_p/2 = 0.2 mm. The wall will pass it, so the wall's
// normal (radial, no axial component) acts and a point at rest feels no
// impulse. Picking the facet that "sees it most from outside" instead gave it
// the bevel normal (0.34 axial, 0.94 across the needle): such points were
// pushed across the needle's path and the tissue was driven ahead of the bevel
// (the local model's tip force rose to 5 N and stopped at 18 mm). The same
// point 0.01 mm inside the radius is swept by the bevel face: pure normal
// impulse of the bevel, axial share sin(20 deg) of the force, on the tip.
TEST(MpmCfempBevel, SharpPointNormalFromTheFacetThatSweepsThePoint) {
  const RigidForce in = forceFromOnePoint(0.15e-3, -0.01e-3);
  ASSERT_GT(in.tip.norm(), 0.0);
  EXPECT_EQ(in.shaft.norm(), 0.0);
  // Rigid needle, no friction: the force is along -n of the bevel facet (planar
  // fan, exact normal): x share -sin(20 deg), y share +cos(20 deg).
  const double s20 = std::sin(20.0 * std::numbers::pi / 180.0);
  EXPECT_NEAR(in.tip.x() / in.tip.norm(), -s20, 1e-9);
  EXPECT_NEAR(in.tip.y() / in.tip.norm(), std::sqrt(1 - s20 * s20), 1e-9);

  const RigidForce out = forceFromOnePoint(0.15e-3, 0.01e-3);
  EXPECT_EQ(out.tip.norm(), 0.0) << "a point outside the radius took the bevel normal";
  EXPECT_LT(out.total.norm(), 1e-9 * in.tip.norm());

  // Out of reach (0.25 mm from the sharp point > d_p/2): no contact at all.
  const RigidForce far = forceFromOnePoint(0.25e-3, -0.01e-3);
  EXPECT_EQ(far.total.norm(), 0.0);
}

// The local model of seed 000 section 4.3 reduced for speed (examples/mpm/
// local_model.yaml with a 6 x 6 x 14 mm block, 11 mm insertion, d_e = 0;
// 5,600 points, about 8 s): with the tie rule above the tissue parts ahead of
// the bevel (measured: tip force peaks at 0.75 N at 9.1 mm, 0.11 N at 11 mm);
// with the largest-dot tie-break it was driven ahead of the bevel and the tip
// force climbed to 1.35 N at 9.9 mm (the full model then stopped at 18 mm).
// Bound: 0.8 N, about the geometric mean of the two. The tie rule in one velocity
// field (parting: none): with the parting contact the tip force stays near 0.04 N
// throughout (test_mpm_parting.cpp).
TEST(MpmCfempBevel, LongReducedLocalModelTipForceLevelsOff) {
  const std::string yaml = R"(name: reduced_local_model
tissue:
  block: {length: 14 mm, width: 6 mm, height: 6 mm}
  material: {name: pva_illustrative, law: fung, mu: 10 kPa, gamma: 1.0, nu: 0.475, density: 1000 kg/m^3}
  friction: {coefficient: 0.255}
needle: {outer_diameter: 20 G, length: 40 mm, tip: bevel, bevel_angle: 20 deg}
insertion:
  start_depth: -0.5 mm
  profile:
    - insert: {to: 11 mm, speed: 6 mm/s}
model:
  engine: mpm
  mpm:
    grid_spacing: 0.8 mm
    particle_spacing: 0.4 mm
    shape: bspline
    update: musl
    contact: cfemp
    parting: none
    mass_scaling: 1e4
    time_step_factor: 0.4
    threads: 1
    faces: {entry: free, exit: fixed, y_min: non-reflecting, y_max: non-reflecting,
            z_min: non-reflecting, z_max: non-reflecting}
    field_interval: 10 s
output:
  interval: 20 ms
)";
  const Scenario sc = scenario::readText(yaml, "reduced_local_model.yaml");
  MemorySink out;
  const EngineInfo* e = findEngine("mpm");
  ASSERT_NE(e, nullptr);
  e->run(sc, out, RunOptions{false});
  const io::Table& f = out.tables.at("forces");
  const auto depth = f.column("depth"), tip = f.column("force_tip");
  double peak = 0.0, at = 0.0;
  for (std::size_t i = 0; i < f.rows(); ++i)
    if (tip[i] > peak) {
      peak = tip[i];
      at = depth[i];
    }
  std::printf("reduced local model: peak tip force %.3f N at %.2f mm, final tip %.3f N at %.2f mm\n", peak, at * 1e3,
              tip[f.rows() - 1], depth[f.rows() - 1] * 1e3);
  EXPECT_NEAR(depth[f.rows() - 1], 11e-3, 1e-4);  // reached the end
  EXPECT_GT(peak, 0.1);
  EXPECT_LT(peak, 0.8) << "the tissue no longer parts ahead of the bevel";
  EXPECT_LT(tip[f.rows() - 1], 0.5 * peak);  // separated: the tip force fell after its peak
}
