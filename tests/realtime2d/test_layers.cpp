// One tissue in realtime2d: layers (element material, puncture by eq 3.16 with the
// layer's material, Karnopp friction per layer, seed 003 eqs 3.16, 3.23), bonded
// inclusions as material discs of the 2D mesh, and refusals of what it cannot model.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>

#include <fmt/format.h>

#include "needlesim/core/error.hpp"
#include "needlesim/engines/memory_sink.hpp"
#include "needlesim/engines/realtime2d/tissue.hpp"
#include "needlesim/forces/stiffness.hpp"
#include "needlesim/scenario/reader.hpp"

using namespace needlesim;

namespace {
// A 50 x 40 mm block of two layers (20 + 30 mm) and optional extra tissue lines.
std::string twoLayers(const std::string& layer1, const std::string& layer2, const std::string& extra,
                      const std::string& speed, const std::string& to, int nodesDepth = 11) {
  return fmt::format(R"(name: layers
tissue:
  block: {{length: 50 mm, width: 40 mm, height: 20 mm}}
  layers:
    - {{name: soft, thickness: 20 mm, {}}}
    - {{name: stiff, thickness: 30 mm, {}}}
{}needle: {{outer_diameter: 18 G, length: 100 mm, bevel_angle: 30 deg, tip: bevel}}
insertion:
  start_depth: -0.5 mm
  profile:
    - insert: {{to: {}, speed: {}}}
model:
  engine: realtime2d
  time_step: 1 ms
  realtime2d: {{nodes_depth: {}, nodes_lateral: 13, field_interval: 0 s}}
output: {{interval: 1 ms}}
)",
                     layer1, layer2, extra, to, speed, nodesDepth);
}

const std::string kFriction = "friction: {C_p: 3.791 N/m, b_p: 285.053 N s/m^2}";
}  // namespace

// The second layer's boundary is pressed by eq 3.16 with the second layer's E and nu
// (no cutting meanwhile) until its own puncture force; at equal indentation the force of
// a stiffer layer is larger by E2 (1 - nu1^2) / (E1 (1 - nu2^2)).
TEST(Realtime2dLayers, EachBoundaryIsPuncturedByItsLayersStiffness) {
  const double E1 = 10e3, nu1 = 0.45, E2 = 60e3, nu2 = 0.4, P1 = 0.01, P2 = 0.08;
  const std::string y = twoLayers(
      fmt::format("material: {{law: linear, E: 10 kPa, nu: 0.45}}, puncture: {{force: {} N}}, "
                  "cutting: {{force: 0.04 N}}, {}", P1, kFriction),
      fmt::format("material: {{law: linear, E: 60 kPa, nu: 0.4}}, puncture: {{force: {} N}}, "
                  "cutting: {{force: 0.06 N}}, {}", P2, kFriction),
      "", "5 mm/s", "30 mm");
  const MemorySink out = runInMemory(scenario::readText(y, "<layers>"));
  const forces::StiffnessLaw law1{E1, nu1, std::numbers::pi / 6, std::numbers::pi / 2};
  const forces::StiffnessLaw law2{E2, nu2, std::numbers::pi / 6, std::numbers::pi / 2};
  const double xb = 0.02, step = 5e-3 * 1e-3;
  ASSERT_TRUE(out.results.count("puncture_depth_2"));
  EXPECT_NEAR(out.results.at("puncture_depth").value, law1.depthAt(P1) + 0.5 * step, 0.5 * step + 1e-12);
  EXPECT_NEAR(out.results.at("puncture_depth_2").value, xb + law2.depthAt(P2) + 0.5 * step, 0.5 * step + 1e-12);
  const auto& f = out.tables.at("forces");
  const auto depth = f.column("depth"), stiff = f.column("force_stiffness"), cut = f.column("force_cutting"),
             phase = f.column("phase");
  int pressing = 0;
  for (std::size_t i = 0; i < depth.size(); ++i) {
    if (depth[i] <= xb + 1e-9 || depth[i] >= out.results.at("puncture_depth_2").value - 1e-12) continue;
    ++pressing;
    EXPECT_NEAR(stiff[i], law2.force(depth[i] - xb), 1e-12);
    EXPECT_EQ(cut[i], 0.0);
    EXPECT_EQ(phase[i], 1.0);  // Pressing
  }
  EXPECT_GT(pressing, 100);
  EXPECT_NEAR(law2.coefficient() / law1.coefficient(), E2 * (1 - nu1 * nu1) / (E1 * (1 - nu2 * nu2)), 1e-12);
}

// Steady insertion: each mm of new shaft adds the Karnopp force of the layer it lies in
// (eqs 3.23, 5.1), per length between the static limit D_p (a node held while the tissue is
// still dragged along) and the full slip C_p + b_p v (0 <= v_rel <= v). The two layers'
// brackets do not overlap. The slope is a least-squares fit over 12 mm, ten node spacings:
// each newly coupled node adds a saw tooth of one spacing.
TEST(Realtime2dLayers, FrictionSlopeFollowsTheLayer) {
  const std::string y = twoLayers(
      "material: gelatin_10wt, puncture: {force: 0.005 N}, cutting: {force: 0.04 N}, " + kFriction,
      "material: gelatin_10wt, puncture: {force: 0.005 N}, cutting: {force: 0.04 N}, "
      "friction: {C_p: 11.373 N/m, b_p: 285.053 N s/m^2}",
      "", "3 mm/s", "40 mm", 41);
  const MemorySink out = runInMemory(scenario::readText(y, "<friction>"));
  const auto& f = out.tables.at("forces");
  const auto depth = f.column("depth"), fric = f.column("force_friction");
  auto slope = [&](double d0, double d1) {
    double n = 0, sx = 0, sy = 0, sxx = 0, sxy = 0;
    for (std::size_t i = 0; i < depth.size(); ++i) {
      if (depth[i] < d0 || depth[i] > d1) continue;
      n += 1; sx += depth[i]; sy += fric[i]; sxx += depth[i] * depth[i]; sxy += depth[i] * fric[i];
    }
    return (n * sxy - sx * sy) / (n * sxx - sx * sx);
  };
  const double v = 3e-3, s1 = 3.791 + 285.053 * v, s2 = 11.373 + 285.053 * v;
  const double D1 = 3.791 + 285.053 * 0.5e-4, D2 = 11.373 + 285.053 * 0.5e-4;  // C + b static_band / 2
  const double k1 = slope(0.006, 0.018), k2 = slope(0.026, 0.038);
  std::printf("friction slope %.4f N/m (layer 1: D %.4f, C + b v %.4f), %.4f N/m (layer 2: %.4f, %.4f)\n", k1, D1, s1,
              k2, D2, s2);
  EXPECT_GT(k1, 0.97 * D1);
  EXPECT_LT(k1, 1.03 * s1);
  EXPECT_GT(k2, 0.97 * D2);
  EXPECT_LT(k2, 1.03 * s2);
}

namespace {
needlesim::realtime2d::TissueConfig block(double inclusionE) {
  needlesim::realtime2d::TissueConfig c;
  c.mesh.length = 0.05;
  c.mesh.width = 0.04;
  c.mesh.nodes_depth = 21;
  c.mesh.nodes_lateral = 17;
  c.mesh.path_y = 0.02;
  c.backend = needlesim::realtime2d::Backend::Direct;
  if (inclusionE > 0.0) {
    needlesim::realtime2d::MaterialRegion r;
    r.centre = {0.0125, 0.02};  // on the path, 5 elements deep
    r.radius = 4e-3;
    r.material = c.material;
    r.material.E = inclusionE;
    c.regions.push_back(r);
  }
  return c;
}
}  // namespace

// A stiffer inclusion adds a positive semi-definite part to K (and to the Newmark matrix
// A = K (1 + a1 beta) + M (a0 + a1 alpha)), so no path compliance can grow (S = G^T A^-1 G
// falls in the Loewner order) and a softer one can shrink none; the change is local: the
// path node in the disc loses more compliance than one 25 mm away.
TEST(Realtime2dInclusions, StiffnessChangesLocally) {
  using needlesim::realtime2d::Tissue;
  const Eigen::Vector2d entry(0.0, 0.02), axis(1.0, 0.0);
  const Tissue plain(block(0.0), entry, axis, 1e-3);
  const double E = block(0.0).material.E;
  const Tissue stiff(block(10 * E), entry, axis, 1e-3);
  const Tissue soft(block(0.1 * E), entry, axis, 1e-3);
  const auto &S0 = plain.pathCompliance(), &S1 = stiff.pathCompliance(), &S2 = soft.pathCompliance();
  ASSERT_EQ(S0.rows(), S1.rows());
  for (Eigen::Index k = 0; k < S0.rows(); ++k) {
    EXPECT_LE(S1(k, k), S0(k, k) * (1 + 1e-10)) << k;
    EXPECT_GE(S2(k, k), S0(k, k) * (1 - 1e-10)) << k;
  }
  // Path node i lies at x = 2.5 mm i: node 5 at the disc centre, node 15 25 mm beyond it.
  auto drop = [&](int i) { return 1.0 - S1(2 * i, 2 * i) / S0(2 * i, 2 * i); };
  EXPECT_NEAR(plain.path()[5].s, 0.0125, 1e-12);
  EXPECT_GT(drop(5), 10 * drop(15));
  EXPECT_GT(drop(5), 0.0);
}

// A bonded target beside the path is dragged forward by the shaft friction (like the
// markers of the thesis example) and reported through inclusions.csv.
TEST(Realtime2dInclusions, BondedTargetIsDraggedAndReported) {
  const std::string layer = "material: gelatin_10wt, puncture: {force: 0.02 N}, cutting: {force: 0.04 N}, " + kFriction;
  const std::string y = twoLayers(layer, layer,
                                  "  inclusions:\n"
                                  "    - {name: tumour, shape: cylinder, depth: 12 mm, lateral: 4 mm, radius: 3 mm,\n"
                                  "       material: {law: linear, E: 90 kPa, nu: 0.45}, target: true}\n",
                                  "5 mm/s", "25 mm");
  const MemorySink out = runInMemory(scenario::readText(y, "<inclusion>"));
  ASSERT_TRUE(out.tables.count("inclusions"));
  EXPECT_EQ(out.tables.at("inclusions").rows(), out.tables.at("forces").rows());
  EXPECT_GT(out.results.at("tumour_shift_axial").value, 0.0);
  EXPECT_GT(out.results.at("tumour_displacement_max").value, 0.0);
}

namespace {
std::string refusedField(const std::string& yaml) {
  try {
    runInMemory(scenario::readText(yaml, "<refused>"));
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("realtime2d"), std::string::npos) << e.what();
    return e.field();
  }
  return "accepted";
}
}  // namespace

TEST(Realtime2dInclusions, RefusesWhatThe2dMeshCannotModel) {
  const std::string layer = "material: gelatin_10wt, puncture: {force: 0.02 N}, cutting: {force: 0.04 N}, " + kFriction;
  EXPECT_EQ(refusedField(twoLayers(layer, layer,
                                   "  inclusions:\n    - {depth: 12 mm, radius: 3 mm, interface: sliding,\n"
                                   "       material: {law: linear, E: 90 kPa, nu: 0.45}}\n",
                                   "5 mm/s", "5 mm")),
            "tissue.inclusions[0].interface");
  EXPECT_EQ(refusedField(twoLayers(layer, layer,
                                   "  inclusions:\n    - {depth: 12 mm, elevation: 5 mm, radius: 3 mm,\n"
                                   "       material: {law: linear, E: 90 kPa, nu: 0.45}}\n",
                                   "5 mm/s", "5 mm")),
            "tissue.inclusions[0].elevation");
  const std::string relaxing =
      "material: {law: linear, E: 30 kPa, nu: 0.45, prony: [{g: 0.3, tau: 1 s}]}, puncture: {force: 0.02 N}, "
      "cutting: {force: 0.04 N}, " + kFriction;
  EXPECT_EQ(refusedField(twoLayers(layer, relaxing, "", "5 mm/s", "5 mm")), "tissue.layers[1].material.prony");
}
