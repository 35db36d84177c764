// The explicit engine in the shared insertion frame and tissue (needle/insertion_frame.hpp,
// scenario tissue.layers and tissue.inclusions), on small 2D plane-strain blocks (under a second each):
//  - a bevel tip is pushed away from its face: force_lateral < 0 at bevel_orientation 0 (the face
//    looks to +lateral), > 0 at 180 deg (3D: ExplicitNeedleRotation.BevelRotated180MirrorsLateralForce);
//  - an oblique needle tilts towards +y: the tip lies at entry + depth (sin t, cos t);
//  - wall friction per layer: a second layer with another coefficient changes the shaft friction once
//    the shaft reaches it and nothing before;
//  - a bonded inclusion: a stiffer one on the path raises the force when the tip reaches it; a target
//    beside the path moves opposite to the lateral force on the needle (action and reaction); a sliding
//    one is refused.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "engine_tables.hpp"
#include "needlesim/core/error.hpp"
#include "needlesim/engines/memory_sink.hpp"
#include "needlesim/scenario/reader.hpp"

using namespace needlesim;

namespace {

const char* kMaterial = "{law: neo-hookean, C10: 3.6 kPa, nu: 0.45, density: 1000 kg/m^3}";

struct Case {
  std::string tissue = std::string("  material: ") + kMaterial + "\n  friction: {coefficient: 0.3}\n";
  std::string tip = "bevel";
  std::string insertion = "  entry_angle: 90 deg\n";
  std::string depth = "5 mm";
  std::string preCut = "true";
};

std::string yaml(const Case& c) {
  return R"(
name: frame_tissue
tissue:
  block: {length: 10 mm, width: 10 mm, height: 10 mm}
)" + c.tissue + R"(needle: {outer_diameter: 2 mm, length: 30 mm, bevel_angle: 45 deg, tip: )" + c.tip + R"(, youngs_modulus: 200 GPa}
insertion:
)" + c.insertion + R"(  start_depth: -0.5 mm
  profile:
    - insert: {to: )" + c.depth + R"(, speed: 10 mm/s}
model:
  engine: explicit
  explicit:
    dimension: 2d
    element: quad4
    element_size: 0.5 mm
    max_element_size: 2 mm
    core_width: 4 mm
    mass_scaling: 15
    tip_friction: 0
    pre_cut: )" + c.preCut + R"(
output: {interval: 10 ms}
)";
}

MemorySink run(const Case& c) { return runInMemory(scenario::readText(yaml(c), "<frame_tissue>")); }

// mean of a forces.csv column over the rows with depth in [d0, d1]
double meanOver(const MemorySink& m, const char* col, double d0, double d1) {
  const auto depth = explicit_test::column(m, "forces", "depth"), v = explicit_test::column(m, "forces", col);
  double s = 0;
  int n = 0;
  for (std::size_t i = 0; i < v.size(); ++i)
    if (depth[i] >= d0 && depth[i] <= d1) s += v[i], ++n;
  return n ? s / n : NAN;
}

std::string layers(double mu1, double mu2) {
  return "  layers:\n    - {name: skin, thickness: 3 mm, material: " + std::string(kMaterial) +
         ", friction: {coefficient: " + std::to_string(mu1) + "}}\n    - {name: muscle, thickness: 7 mm, material: " +
         kMaterial + ", friction: {coefficient: " + std::to_string(mu2) + "}}\n";
}

}  // namespace

TEST(ExplicitFrame, BevelIsPushedAwayFromItsFace) {
  Case c;
  c.depth = "3 mm";
  const MemorySink b0 = run(c);
  c.insertion += "  bevel_orientation: 180 deg\n";
  const MemorySink b180 = run(c);
  const double f0 = meanOver(b0, "force_lateral", 1.5e-3, 3e-3), f180 = meanOver(b180, "force_lateral", 1.5e-3, 3e-3);
  std::printf("mean lateral force 1.5-3 mm: bevel 0 %.4g N, bevel 180 %.4g N (axial %.4g N)\n", f0, f180,
              meanOver(b0, "force_total", 1.5e-3, 3e-3));
  EXPECT_LT(f0, 0.0);
  EXPECT_GT(f180, 0.0);
}

// Kinematics of the rigid needle: tip = entry + depth axial, axial = (sin t, cos t, 0); a cone's apex is
// the leading point. The needle indents the block (no pre-cut seam off the normal direction).
TEST(ExplicitFrame, ObliqueInsertionTiltsTowardsPlusY) {
  Case c;
  c.tip = "conical";
  c.insertion = "  entry_angle: 60 deg\n  entry_offset: -1 mm\n";
  c.depth = "1.5 mm";
  c.preCut = "false";
  const MemorySink m = run(c);
  const double d = explicit_test::column(m, "forces", "depth").back();
  const double x = explicit_test::column(m, "forces", "tip_x").back(), y = explicit_test::column(m, "forces", "tip_y").back();
  const double th = M_PI / 3;
  std::printf("oblique 60 deg: depth %.4g mm, tip (%.4g, %.4g) mm, axial force %.4g N\n", d * 1e3, x * 1e3, y * 1e3,
              explicit_test::column(m, "forces", "force_total").back());
  EXPECT_NEAR(d, 1.5e-3, 1e-12);
  EXPECT_NEAR(x, d * std::sin(th), 1e-12);
  EXPECT_NEAR(y, -1e-3 + d * std::cos(th), 1e-12);
  EXPECT_GT(y, -1e-3);
  EXPECT_GT(explicit_test::column(m, "forces", "force_total").back(), 0.0);  // the tissue resists
}

// Friction 0.3 in a 3 mm skin over muscle with 0 (or 0.3): until the tip nears the skin's end (one element
// before it) the contact never touches the muscle and the runs agree to round-off; beyond, the shaft in the
// muscle slides freely. The shaft friction force is the rate of the friction dissipation with the travel
// (Coulomb force x slip, the tissue nearly at rest along the shaft): between 5 and 6 mm it is smaller with
// the frictionless muscle than with 0.3 everywhere and larger than with no friction. Equal coefficients
// reproduce the one-layer run.
TEST(ExplicitLayers, WallFrictionPerLayer) {
  Case c;
  c.depth = "6 mm";
  c.tissue = layers(0.3, 0.3);
  const MemorySink same = run(c);
  c.tissue = layers(0.3, 0.0);
  const MemorySink skin = run(c);
  c.tissue = std::string("  material: ") + kMaterial + "\n  friction: {coefficient: 0.3}\n";
  const MemorySink all = run(c);
  c.tissue = std::string("  material: ") + kMaterial + "\n  friction: {coefficient: 0}\n";
  const MemorySink none = run(c);
  auto shaftFriction = [](const MemorySink& m) {  // d(friction dissipation) / d(depth) over 5-6 mm
    const auto d = explicit_test::column(m, "energy", "depth"), D = explicit_test::column(m, "energy", "friction_dissipation");
    std::size_t i = 0, j = 0;
    while (i + 1 < d.size() && d[i] < 5e-3) ++i;
    while (j + 1 < d.size() && d[j] < 6e-3 - 1e-9) ++j;
    return (D[j] - D[i]) / (d[j] - d[i]);
  };
  const double qAll = shaftFriction(all), qSkin = shaftFriction(skin), qNone = shaftFriction(none);
  std::printf("shaft friction force 5-6 mm: mu 0.3 %.4g N, skin 0.3 / muscle 0 %.4g N, mu 0 %.4g N\n", qAll, qSkin, qNone);
  const auto a = explicit_test::column(all, "forces", "force_total"), s = explicit_test::column(same, "forces", "force_total");
  const auto k = explicit_test::column(skin, "forces", "force_total"), d = explicit_test::column(all, "forces", "depth");
  ASSERT_EQ(a.size(), s.size());
  ASSERT_EQ(a.size(), k.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i], s[i]) << "row " << i;
    if (d[i] < 3e-3 - 0.5e-3) EXPECT_NEAR(k[i], a[i], 1e-12 * std::abs(a[i]) + 1e-15) << "row " << i;
  }
  EXPECT_EQ(qNone, 0.0);
  EXPECT_GT(qSkin, 0.0);
  EXPECT_LT(qSkin, qAll);
}

// A stiff inclusion (E x 10) of radius 1.5 mm centred 4 mm deep on the path: past its front (2.5 mm) the
// needle cuts (and wedges open) stiffer material, so the contact force is larger than in the homogeneous block.
TEST(ExplicitInclusions, StiffInclusionOnThePathRaisesTheForce) {
  Case c;
  const MemorySink plain = run(c);
  c.tissue += "  inclusions:\n    - {name: nodule, depth: 4 mm, lateral: 0 mm, radius: 1.5 mm, material: "
              "{law: neo-hookean, C10: 36 kPa, nu: 0.45, density: 1000 kg/m^3}}\n";
  const MemorySink stiff = run(c);
  const double f0 = meanOver(plain, "force_total", 3e-3, 5e-3), f1 = meanOver(stiff, "force_total", 3e-3, 5e-3);
  const double e0 = meanOver(plain, "force_total", 0.5e-3, 1.5e-3), e1 = meanOver(stiff, "force_total", 0.5e-3, 1.5e-3);
  std::printf("axial force 3-5 mm: homogeneous %.4g N, stiff inclusion %.4g N; 0.5-1.5 mm: %.4g / %.4g N\n", f0, f1, e0, e1);
  EXPECT_GT(f1, 1.5 * f0);
  ASSERT_TRUE(stiff.tables.count("inclusions"));
  EXPECT_EQ(stiff.tables.at("inclusions").rows(), stiff.tables.at("forces").rows());
}

// A target 3 mm beside the path on the bevel side (+y): at bevel 0 the bevel face pushes the upper lip of
// the cut towards +y and the tissue pushes the needle towards -y (force_lateral < 0), so the target moves
// towards +y: its lateral shift has the sign of the force the needle gives the tissue, -force_lateral.
TEST(ExplicitInclusions, TargetMovesWithTheForceTheNeedleGivesIt) {
  Case c;
  c.tissue += "  inclusions:\n    - {name: target, depth: 4 mm, lateral: 3 mm, radius: 1 mm, target: true, material: " +
              std::string(kMaterial) + "}\n";
  const MemorySink m = run(c);
  const double shift = m.results.at("target_shift_lateral").value;
  const double f = meanOver(m, "force_lateral", 3e-3, 5e-3);
  std::printf("target lateral shift %.4g um, mean lateral force on the needle 3-5 mm %.4g N\n", shift * 1e6, f);
  EXPECT_LT(f, 0.0);
  EXPECT_GT(shift, 0.0);
}

TEST(ExplicitInclusions, SlidingInclusionIsRefused) {
  Case c;
  c.tissue += "  inclusions:\n    - {depth: 4 mm, radius: 1 mm, interface: sliding, material: " + std::string(kMaterial) +
              "}\n";
  try {
    run(c);
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    const std::string msg = e.what();
    for (const char* part : {"tissue.inclusions[0].interface", "'sliding'", "needs tissue-tissue contact",
                             "interface: bonded, or engine mpm"})
      EXPECT_NE(msg.find(part), std::string::npos) << part << " not in: " << msg;
  }
}
