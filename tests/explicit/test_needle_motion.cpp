// Needle rotation from the insertion profile (needle_motion.hpp): a 3D bevel needle (30 deg,
// frictionless, no pre-cut) indents a block 1.5 mm past the surface. The bevel face presses the
// surface on one side of the axis, so the tissue pushes the needle sideways. Rotating the needle
// 180 deg about its axis (profile `rotate`, before it touches the tissue) mirrors the geometry
// about the plane through the axis, so the lateral force (insertion frame) changes sign and
// equals that of a needle set up with bevel_orientation 180 deg; the axial force is unchanged.
// A needle rotated while pressed into the tissue with friction feels a torque about its axis
// opposing the rotation, bounded by mu x normal force x outer radius (Coulomb).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "needlesim/engines/memory_sink.hpp"
#include "needlesim/scenario/reader.hpp"

using namespace needlesim;

namespace {

std::string yaml(const std::string& bevel, const std::string& profile, const std::string& tipFriction) {
  return R"(
name: needle_rotation
tissue:
  block: {length: 6 mm, width: 8 mm, height: 8 mm}
  material: {law: neo-hookean, C10: 3.6 kPa, nu: 0.45, density: 1000 kg/m^3}
  friction: {coefficient: 0.3}
needle: {outer_diameter: 2 mm, length: 20 mm, bevel_angle: 30 deg, tip: bevel, youngs_modulus: 200 GPa}
insertion:
  entry_angle: 90 deg
  bevel_orientation: )" + bevel + R"(
  start_depth: -0.3 mm
  profile:
)" + profile + R"(
model:
  engine: explicit
  explicit:
    dimension: 3d
    element: hex8
    element_size: 0.5 mm
    max_element_size: 2 mm
    core_width: 4 mm
    mass_scaling: 100
    damping: 200 1/s
    pre_cut: false
    tip_friction: )" + tipFriction + R"(
output: {interval: 5 ms}
)";
}

struct Out {
  double axial, lateral, torque, bevel;
};

Out run(const std::string& bevel, const std::string& profile, const std::string& tipFriction = "0") {
  MemorySink s = runInMemory(scenario::readText(yaml(bevel, profile, tipFriction), "<rotation>"));
  const auto& t = s.tables.at("forces");
  return {t.column("force_total").back(), t.column("force_lateral").back(), s.results.at("peak_axial_torque").value,
          t.column("bevel_orientation").back()};
}

}  // namespace

TEST(ExplicitNeedleRotation, BevelRotated180MirrorsLateralForce) {
  const std::string insert = "    - insert: {to: 1.5 mm, speed: 20 mm/s}\n";
  const Out a = run("0 deg", insert);
  const Out c = run("180 deg", insert);
  // rotated by the profile in 10 ms before touching the tissue; the reference waits as long so
  // that both see the same time steps
  const Out b = run("0 deg", "    - rotate: {by: 180 deg, rate: 18000 deg/s}\n" + insert);
  const Out cw = run("180 deg", "    - pause: {duration: 10 ms}\n" + insert);
  std::printf("bevel 0: axial %.5g N, lateral %.5g N; bevel 180: axial %.5g, lateral %.5g; rotated 180 by the "
              "profile: axial %.5g, lateral %.5g (bevel %.4f rad), bevel 180 after a pause: axial %.5g, lateral %.5g\n",
              a.axial, a.lateral, c.axial, c.lateral, b.axial, b.lateral, b.bevel, cw.axial, cw.lateral);
  ASSERT_GT(std::abs(a.lateral), 0.05 * a.axial);  // the bevel does push sideways
  // the tissue pushes the tip away from the bevel face (needle/insertion_frame.hpp): at bevel 0 the face
  // looks to +lateral, so the lateral force is < 0; at 180 deg it looks to -lateral, > 0
  EXPECT_LT(a.lateral, 0.0);
  EXPECT_GT(c.lateral, 0.0);
  // bevel 180 is the mirror image (the mesh is symmetric about the plane through the axis)
  EXPECT_NEAR(c.lateral, -a.lateral, 1e-6 * std::abs(a.lateral));
  EXPECT_NEAR(c.axial, a.axial, 1e-6 * a.axial);
  // the profile's rotation puts the needle in the 180 deg pose: the same forces (round-off of the
  // rotated direction only)
  EXPECT_NEAR(std::abs(b.bevel), M_PI, 1e-9);
  EXPECT_NEAR(b.lateral, cw.lateral, 1e-6 * std::abs(a.lateral));
  EXPECT_NEAR(b.axial, cw.axial, 1e-6 * a.axial);
  EXPECT_LT(b.lateral * a.lateral, 0.0);
}

TEST(ExplicitNeedleRotation, RotationInContactFeelsOpposingTorque) {
  const std::string prof = "    - insert: {to: 1.5 mm, speed: 20 mm/s}\n    - rotate: {by: 30 deg, rate: 600 deg/s}\n";
  MemorySink s = runInMemory(scenario::readText(yaml("0 deg", prof, "0.3"), "<torque>"));
  const auto& t = s.tables.at("forces");
  const auto tq = t.column("axial_torque"), f = t.column("force_total"), bev = t.column("bevel_orientation");
  const double torque = tq.back(), R = 1e-3, mu = 0.3;
  // Coulomb bound: |T| <= mu sum(fn) R; sum(fn) >= the axial force (frictionless part on the faces)
  std::printf("rotation in contact: torque %.4g N m, axial force %.4g N, bevel %.3f rad, peak torque %.4g\n", torque,
              f.back(), bev.back(), s.results.at("peak_axial_torque").value);
  EXPECT_NEAR(bev.back(), 30 * M_PI / 180, 1e-6);
  // rotation is +30 deg about the axis: the tissue's torque on the needle is negative (opposes it)
  EXPECT_LT(torque, 0.0);
  EXPECT_LT(std::abs(torque), mu * R * 5 * f.back());  // generous: sum fn <= ~5 x axial on a 30 deg bevel
}
