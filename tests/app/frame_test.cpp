// One scenario through every engine that accepts it (docs/models/frame.md): the
// engines share one frame, so they must agree on the physics' signs, on what each results
// column means, and, where their models coincide, on the force itself.
//  - A bevel tip is pushed away from the side its face looks to (seed 002 section 3,
//    seed 003 section 3.4): at bevel_orientation 0 the face looks to +lateral, so the
//    tissue's lateral force on the needle is < 0 (rigid needles: mpm, explicit; the
//    flexible realtime2d needle as well) and a flexible needle bends to -lateral; at
//    180 deg both change sign. The steering paths curve to -y.
//  - An oblique needle (entry_angle 70 deg) goes towards +y as it goes deeper: every
//    engine puts its tip at y > entry_offset.
//  - Columns: tip_* is the needle's axis at the tip in every engine; force_total is the sum of
//    its parts in every engine that reports them (force_tip + force_shaft; force_stiffness +
//    force_cutting + force_friction).
//  - Agreement: in the friction phase realtime2d and realtime3d carry the lumped model's force
//    (seed 003 eqs 3.23-3.24, the same cutting force and friction law) within the part of it
//    that depends on how fast the tissue slides along the shaft (see AxialForce...), and without
//    that part to rounding wherever no node is held in the static band (WithoutTheSpeedTerm...).
//    explicit 3D and mpm agree with each other only on converged meshes (docs/validation/agreement.md),
//    beyond this block's cost: here they are held to the signs and columns above.
// The block, needle and motion are one text; only model.engine changes between runs
// ("explicit3d": the explicit engine in 3D, on hexahedra).
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "needlesim/engines/memory_sink.hpp"
#include "needlesim/scenario/reader.hpp"

using namespace needlesim;

namespace {

// 12 x 10 x 6 mm soft gel, a 2 mm 45 deg needle pushed 4 mm in: seconds in every engine. explicit
// without its pre-cut slit (with it: PrecutSlit3d.BevelPushesTheNeedleAwayFromItsFace); mpm with its
// grid contact (analytic, mirror-symmetric needle) and ("mpmedges") with its CFEMP contact cutting
// along the bevel's edges (model.mpm.cut: edges, the face frictionless as explicit's): its default
// cut through the axis leaves a bevel's lateral force unresolved and says so
// (MpmDefaults.ABevelsLateralForceIsWarnedAsNotResolvedByTheCutThroughTheAxis).
std::string scenario(std::string engine, const std::string& insertion, const std::string& tip,
                     const std::string& to = "4 mm") {
  std::string explicitModel = "dimension: 2d, element: quad4, element_size: 0.5 mm", mpmContact = "contact: grid";
  if (engine == "mpmedges") {
    engine = "mpm";
    mpmContact = "cut: edges, tip_friction: 0";
  }
  if (engine == "explicit3d") {
    engine = "explicit";
    explicitModel = "dimension: 3d, element: hex8, element_size: 1 mm";
  }
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
    - insert: {to: )" + to + R"(, speed: 10 mm/s}
model:
  engine: )" +
         engine + R"(
  time_step: 1 ms
  realtime2d: {nodes_depth: 13, nodes_lateral: 21, field_interval: 0 s}
  realtime3d: {nodes_depth: 13, nodes_lateral: 11, nodes_height: 7, field_interval: 0 s}
  explicit: {)" + explicitModel + R"(, max_element_size: 2 mm, core_width: 4 mm,
             mass_scaling: 15, tip_friction: 0, pre_cut: false}
  mpm: {grid_spacing: 1 mm, particle_spacing: 0.5 mm, mass_scaling: 1e4, field_interval: 0 s, )" + mpmContact + R"(,
        faces: {exit: fixed, y_min: roller, y_max: roller, z_min: roller, z_max: roller}}
  steering: {increment: 0.5 mm}
output: {interval: 10 ms}
)";
}

MemorySink run(const std::string& engine, const std::string& insertion, const std::string& tip = "bevel",
               const std::string& to = "4 mm") {
  return runInMemory(scenario::readText(scenario(engine, insertion, tip, to), "<frame " + engine + ">"));
}

// 10 mm in with a light puncture (0.002 N): the tissue the press pushed in springs back little after it.
// b_p: the friction's speed term (N s/m^2; the scenario's is 10).
MemorySink runLightPuncture(const std::string& engine, const std::string& insertion, const std::string& b_p = "10") {
  std::string text = scenario(engine, insertion, "conical", "10 mm");
  text.replace(text.find("force: 0.02 N"), 13, "force: 0.002 N");
  text.replace(text.find("b_p: 10 N"), 9, "b_p: " + b_p + " N");
  return runInMemory(scenario::readText(text, "<frame light puncture " + engine + ">"));
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
  for (const char* engine : {"realtime2d", "realtime3d", "explicit", "explicit3d", "mpm", "mpmedges"}) {
    const MemorySink zero = run(engine, std::string(kNormal) + "  bevel_orientation: 0 deg\n");
    const MemorySink half = run(engine, std::string(kNormal) + "  bevel_orientation: 180 deg\n");
    const double f0 = lateMean(zero, "force_lateral"), f180 = lateMean(half, "force_lateral");
    EXPECT_LT(f0, 0.0) << engine;
    EXPECT_GT(f180, 0.0) << engine;
    // mirror images of one another in a block symmetric about the path; realtime3d's tets are all
    // split one way (docs/models/realtime3d.md), so its mesh is not mirror-symmetric: signs only
    if (std::string(engine) != "realtime3d") EXPECT_NEAR(f0, -f180, 0.05 * std::abs(f0)) << engine;
    if (std::string(engine) == "mpmedges") {  // a frictionless 45 deg face pushes along its normal: |lateral| = axial
      const double tip = lateMean(zero, "force_tip");
      EXPECT_NEAR(lateMean(zero, "force_tip_lateral"), -tip, 0.01 * tip);
      EXPECT_NEAR(lateMean(half, "force_tip_lateral"), lateMean(half, "force_tip"), 0.01 * tip);
    }
    if (hasColumn(zero, "forces", "tip_deflection")) {  // a flexible needle
      EXPECT_LT(zero.tables.at("forces").column("tip_deflection").back(), 0.0) << engine;
      EXPECT_GT(half.tables.at("forces").column("tip_deflection").back(), 0.0) << engine;
    }
  }
  EXPECT_LT(run("kinematic", kNormal).tables.at("tip_path").column("tip_y").back(), 0.0);
}

TEST(OneFrame, ObliqueNeedleGoesTowardsPlusYInEveryEngine) {
  const std::string oblique = "  entry_angle: 70 deg\n  entry_offset: 1 mm\n";
  for (const char* engine : {"lumped", "realtime2d", "realtime3d", "explicit", "explicit3d", "mpm"}) {
    const MemorySink m = run(engine, oblique, "conical");
    // the tip at 4 mm along an axis 20 deg off the face normal: y = 1 mm + 4 mm sin 20 deg
    EXPECT_NEAR(lastTipY(m), 1e-3 + 4e-3 * std::sin(20.0 * M_PI / 180.0), 0.1e-3) << engine;
    EXPECT_GT(lateMean(m, "force_total"), 0.0) << engine;
  }
  // a straight path of the kinematic model: conical tip, no curvature
  EXPECT_NEAR(lastTipY(run("kinematic", oblique, "conical")), 1e-3 + 4e-3 * std::sin(20.0 * M_PI / 180.0), 1e-9);
}

// tip_y is the needle's axis at the tip in every engine: the straight axis (y = 0) for a rigid
// needle, the elastic deflection for a flexible one, and never the bevel's sharp point (-R at
// orientation 0 for this 2 mm needle; explicit and mpm give it as sharp_y). force_total is the
// sum of the parts each engine reports, row by row.
TEST(OneFrame, EveryEngineGivesItsColumnsOneMeaning) {
  const std::string bevel0 = std::string(kNormal) + "  bevel_orientation: 0 deg\n";
  for (const char* engine : {"lumped", "realtime2d", "realtime3d", "explicit", "explicit3d", "mpm"}) {
    const MemorySink m = run(engine, bevel0);
    const auto& f = m.tables.at("forces");
    const double axisY = hasColumn(m, "forces", "tip_deflection") ? f.column("tip_deflection").back() : 0.0;
    EXPECT_NEAR(f.column("tip_y").back(), axisY, 1e-9) << engine;
    if (hasColumn(m, "forces", "sharp_y")) EXPECT_NEAR(f.column("sharp_y").back(), -1e-3, 1e-9) << engine;
    const auto total = f.column("force_total");
    const bool tipShaft = hasColumn(m, "forces", "force_tip"), parts = hasColumn(m, "forces", "force_friction");
    EXPECT_TRUE(tipShaft || parts) << engine;
    for (std::size_t r = 0; r < total.size(); ++r) {
      const double tol = 1e-12 + 1e-9 * std::abs(total[r]);
      if (tipShaft) ASSERT_NEAR(total[r], f.column("force_tip")[r] + f.column("force_shaft")[r], tol) << engine << " row " << r;
      if (parts)
        ASSERT_NEAR(total[r], f.column("force_stiffness")[r] + f.column("force_cutting")[r] + f.column("force_friction")[r], tol)
            << engine << " row " << r;
    }
  }
}

// The lumped model and the real-time engines share eq 3.16 (puncture), eq 3.24 (cutting 0.05 N)
// and the friction law (eq 3.23, C_p 1 N/m, b_p 10 N s/m^2) over the shaft in the tissue, L = the
// depth. They differ in one thing: the lumped shaft slides past the tissue at the needle's speed v,
// the FE tissue moves (dragged along by the friction, pushed ahead by the cutting load and springing
// back as the tip passes), so its v_rel differs from v, by less than v itself while the needle moves
// at a steady speed. While cutting at v = 10 mm/s, two node spacings past the entry, the real-time
// force is therefore the lumped force within b_p v L (0.1 N/m x L, 9 % of the friction, 1 mN at
// 10 mm); a share of the 0.05 N cutting force counted twice would exceed it.
TEST(OneFrame, AxialForceOfTheRealtimeEnginesIsTheLumpedForceWithinTheSlidingSpeedPart) {
  const std::string bevel0 = std::string(kNormal) + "  bevel_orientation: 0 deg\n";
  const MemorySink lumped = runLightPuncture("lumped", bevel0);
  const auto& L = lumped.tables.at("forces");
  const auto Ld = L.column("depth"), Lf = L.column("force_total");
  const double v = 10e-3, bv = 10.0 * v;  // b_p v, N/m
  for (const char* engine : {"realtime2d", "realtime3d"}) {
    const MemorySink m = runLightPuncture(engine, bevel0);
    const auto& f = m.tables.at("forces");
    const auto d = f.column("depth"), F = f.column("force_total"), phase = f.column("phase"), vel = f.column("velocity");
    int compared = 0;
    for (std::size_t r = 0; r < d.size(); ++r) {
      if (phase[r] != 2 || d[r] < 2e-3 || vel[r] < v - 1e-12) continue;  // cutting at v, past two node spacings
      std::size_t k = 0;
      while (k + 1 < Ld.size() && Ld[k] < d[r] - 1e-12) ++k;
      ASSERT_NEAR(Ld[k], d[r], 1e-9) << "the rows are at the same times";
      EXPECT_NEAR(F[r], Lf[k], bv * d[r]) << engine << " at " << d[r] * 1e3 << " mm";
      ++compared;
    }
    EXPECT_GT(compared, 50) << engine;
  }
}

// Without the speed term (b_p = 0) a sliding node carries C_p l, and the nodes' contact lengths l add
// up to the shaft from the entry face to the tip (clamped there, whatever the nodes' displacements):
// in every row where no node is held in the static band both real-time engines' force is the lumped
// model's F_cut + C_p L, the same sum up to rounding (1 uN; the smallest defect it guards, a node's
// length wrong by half a spacing, is C_p h / 2 = 0.5 mN here, a cutting force counted twice 50 mN).
// Past two node spacings, as above: the press pushes the entry node in (the dimple), and it carries
// friction only once the tip passes it again, which the lumped model has no dimple for.
TEST(OneFrame, WithoutTheSpeedTermTheRealtimeEnginesCarryTheLumpedForceWhileEveryNodeSlides) {
  const std::string bevel0 = std::string(kNormal) + "  bevel_orientation: 0 deg\n";
  const MemorySink lumped = runLightPuncture("lumped", bevel0, "0");
  const auto Lf = lumped.tables.at("forces").column("force_total"), Ld = lumped.tables.at("forces").column("depth");
  for (const char* engine : {"realtime2d", "realtime3d"}) {
    const auto& f = runLightPuncture(engine, bevel0, "0").tables.at("forces");
    const auto d = f.column("depth"), F = f.column("force_total"), phase = f.column("phase"),
               stick = f.column("sticking_nodes");
    int compared = 0, held = 0;
    for (std::size_t r = 0; r < d.size() && r < Ld.size(); ++r) {
      if (phase[r] != 2 || d[r] < 2e-3) continue;
      if (stick[r] > 0) { ++held; continue; }  // 8 mm at a row per 0.1 mm: 80 rows
      ASSERT_NEAR(Ld[r], d[r], 1e-12) << "the rows are at the same times";
      EXPECT_NEAR(F[r], Lf[r], 1e-6) << engine << " at " << d[r] * 1e3 << " mm";
      ++compared;
    }
    EXPECT_GT(compared, 70) << engine << " (" << held << " rows with a node held)";
  }
}
