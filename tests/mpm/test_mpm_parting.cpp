// The needle's cut in mpm (model.mpm.parting, needle_cut.cpp): on the reduced reference insertion
// (examples/agreement/reduced.yaml) mpm's axial force is grid-independent and agrees with
// explicit 3D's (docs/validation/agreement.md "explicit 3D vs mpm"), and the peak force of seed
// 000's reduced local model does not depend on where the path lies in the lattice. The elastic
// bounds of the defaults: test_mpm_defaults.cpp.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <string>
#include <utility>

#include "needlesim/engines/memory_sink.hpp"
#include "needlesim/scenario/reader.hpp"

using namespace needlesim;

namespace {

const std::string kReduced = std::string(NEEDLESIM_SOURCE_DIR) + "/examples/agreement/reduced.yaml";

// The reduced reference through `engine`, its model.mpm changed by `change`.
MemorySink runReduced(const std::string& engine, const std::function<void(MpmModelSpec&)>& change = {}) {
  Scenario sc = scenario::readFile(kReduced);
  if (change) change(sc.model.mpm);
  sc.model.engine = engine;
  sc.output.html = false;
  return runInMemory(sc);
}

// The reduced reference through explicit 3D with its core's elements `size` (m) wide.
MemorySink runReducedExplicit(double size) {
  Scenario sc = scenario::readFile(kReduced);
  sc.model.engine = "explicit";
  sc.model.explicit_fe.element_size = size;
  sc.output.html = false;
  return runInMemory(sc);
}

// Mean of a force column (force_total: the axial force) over the rows with the tip between d0
// and d1 (m): the force of a particle or node lattice sliding past the needle rises and falls
// with the lattice.
double meanForce(const MemorySink& m, double d0, double d1, const std::string& column = "force_total") {
  const auto& t = m.tables.at("forces");
  const auto depth = t.column("depth"), f = t.column(column);
  double sum = 0.0;
  int n = 0;
  for (std::size_t r = 0; r < depth.size(); ++r)
    if (depth[r] >= d0 && depth[r] <= d1) {
      sum += f[r];
      ++n;
    }
  EXPECT_GT(n, 4) << "depths " << d0 << "-" << d1 << " m not reached";
  return n > 0 ? sum / n : 0.0;
}

// Seed 000's local model reduced for speed (as test_mpm_cfemp_bevel.cpp: a 6 x 6 x 14 mm Fung
// block, 20 G 20 deg bevel, 11 mm at 6 mm/s, CFEMP, 0.8 mm grid, 0.4 mm points), its entry moved
// across the lattice by `offset`.
std::string reducedLocalModel(const std::string& offset) {
  return R"(name: reduced_local_model
tissue:
  block: {length: 14 mm, width: 6 mm, height: 6 mm}
  material: {name: pva_illustrative, law: fung, mu: 10 kPa, gamma: 1.0, nu: 0.475, density: 1000 kg/m^3}
  friction: {coefficient: 0.255}
needle: {outer_diameter: 20 G, length: 40 mm, tip: bevel, bevel_angle: 20 deg}
insertion:
  start_depth: -0.5 mm
  entry_offset: )" + offset + R"(
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
    mass_scaling: 1e4
    time_step_factor: 0.4
    threads: 1
    faces: {entry: free, exit: fixed, y_min: non-reflecting, y_max: non-reflecting,
            z_min: non-reflecting, z_max: non-reflecting}
    field_interval: 10 s
output:
  interval: 20 ms
)";
}

double peakForce(const MemorySink& m) {
  const auto f = m.tables.at("forces").column("force_total");
  return *std::max_element(f.begin(), f.end());
}

}  // namespace

// Reduced reference insertion, mean axial force with the tip 6-8 mm deep (the block's fixed far
// face is still 4 mm ahead; fracture has no part here: both engines part the tissue along the same
// slit). Grid independence: CFEMP places the needle surface at the material points, within the
// eq 22 gap d_p/2 of a point's centre, so the needle's effective outline, and with it each lip's
// opening and the wall pressure p ~ E* opening / (2R), is uncertain by about d_p / (4R) on each
// grid: between the 0.375 mm and 0.25 mm lattices by at most (0.375 + 0.25) / (4 x 0.635) = 25 %.
// explicit 3D on cores of 0.5 / 0.35 / 0.25 mm elements (46.2 / 48.8 / 50.5 mN; 51.9 at 0.18 mm,
// docs/validation/agreement.md): its differences must contract (a positive observed order, or the
// mesh is not converging), and mpm is compared with the Richardson limit they give. Agreement:
// mpm at 0.25 mm points resolves the outline within d_p / (4R) = 10 %, and the limit carries the
// uncertainty of an order measured on three meshes (the 0.18 mm core moves it by about as much):
// 25 % holds both. The default cut through the axis and explicit's slit through the sharp point
// open the same total width, so the same axial force to first order (docs/validation/agreement.md
// "Which lip moves"). mpm cutting along the bevel's edges (cut: edges) with explicit's frictionless
// face (tip_friction: 0) is held on its lateral force only: its axial force is within 25 % of
// explicit's at this file's mass scaling 1e4 (58.8 mN) but not quasi-static (1e2, four placements:
// 72.7 mN, +40 %, its tip force 1.8x explicit's where its smaller lift should give at most as
// much), so a check of it here would hold inertia, not the cut. Its lateral force must point away
// from the face as explicit's: it is the difference of the two lips' pressures on the shaft, each
// uncertain by the same 10 % + 13 % (explicit's polygon, below), so the two may differ by up to
// 23 % of the shaft's normal load, its friction over mu. One velocity field across the path
// (parting: none) gives 165 mN on the 0.25 mm lattice, 3.6 times explicit's 46 mN.
TEST(MpmParting, LongAgreesWithExplicit3dOnTheReducedReference) {
  double fe[3];
  const double sizes[3] = {0.5e-3, 0.35e-3, 0.25e-3};
  MemorySink finest;
  for (int i = 0; i < 3; ++i) {
    MemorySink ex = runReducedExplicit(sizes[i]);
    fe[i] = meanForce(ex, 6e-3, 8e-3);
    if (i == 2) finest = std::move(ex);
  }
  const double d1 = fe[1] - fe[0], d2 = fe[2] - fe[1];
  ASSERT_GT(d1 * d2, 0.0) << "explicit 3D oscillates with the core: " << fe[0] << ", " << fe[1] << ", " << fe[2] << " N";
  ASSERT_LT(std::abs(d2), std::abs(d1)) << "explicit 3D does not converge with the core: " << fe[0] * 1e3 << " / "
                                        << fe[1] * 1e3 << " / " << fe[2] * 1e3 << " mN";
  const double r = sizes[1] / sizes[2], order = std::log(d1 / d2) / std::log(sizes[0] / sizes[1]);
  const double limit = fe[2] + d2 / (std::pow(r, order) - 1.0);
  const MemorySink fine = runReduced("mpm");
  const MemorySink coarse = runReduced("mpm", [](MpmModelSpec& m) {
    m.grid_spacing = 0.75e-3;
    m.particle_spacing = 0.375e-3;
  });
  const MemorySink edges = runReduced("mpm", [](MpmModelSpec& m) {
    m.cut = "edges";
    m.tip_friction = 0.0;
  });
  const double ff = meanForce(fine, 6e-3, 8e-3), fc = meanForce(coarse, 6e-3, 8e-3);
  EXPECT_LT(std::abs(fc - ff), 0.25 * ff) << "mpm 0.75 mm grid " << fc * 1e3 << " mN, 0.5 mm grid " << ff * 1e3 << " mN";
  EXPECT_LT(std::abs(ff - limit), 0.25 * limit)
      << "mpm " << ff * 1e3 << " mN, explicit 3D's limit " << limit * 1e3 << " mN (order " << order << ")";
  const double le = meanForce(finest, 6e-3, 8e-3, "force_lateral"), lg = meanForce(edges, 6e-3, 8e-3, "force_lateral");
  const double shaftLoad = meanForce(finest, 6e-3, 8e-3, "force_shaft") / 0.25;  // the reference's mu
  EXPECT_LT(le, 0.0) << "explicit 3D's bevel pushes the needle away from its face";
  EXPECT_LT(lg, 0.0) << "mpm cutting along the edges: lateral " << lg * 1e3 << " mN";
  EXPECT_LT(std::abs(lg - le), 0.23 * shaftLoad)
      << "lateral: mpm " << lg * 1e3 << " mN, explicit 3D " << le * 1e3 << " mN, shaft load " << shaftLoad * 1e3 << " mN";
}

// The reduced reference quasi-static (mass scaling 1e2) on the 0.75 mm grid, each cut averaged over
// four placements of the path across a point spacing (insertion.entry_offset 0, d_p/4, d_p/2,
// 3 d_p/4: a single placement scatters by 23-46 % at 1e2), mean forces with the tip 6-8 mm deep. What
// a cut's choice of lip decides (docs/validation/agreement.md "Which lip moves"; linear elasticity,
// the block symmetric about the cut): the part of the lips' displacement that opens the slit presses
// both on the needle alike, the part that moves both the same way adds on one lip what it takes off
// the other, and their energies add. So (1) the shaft's friction is the same for the cut through the
// axis (each lip opened by half the section) and the cut along the edges (the bevel-side lip lifted by
// all of it): within 25 %, CFEMP's outline uncertainty d_p / (4R) = 15 % on this lattice plus the
// placement means' standard errors (up to 9 %); (2) the tip's force, the energy the wake keeps per
// unit length, is smaller for the axis cut, which stores no energy in a common motion of the lips;
// (3) the edges cut pushes the needle away from the face, the axis cut does not push to first order
// (its lateral force, a lip imbalance, is not asserted); (4) the axis cut's axial force is explicit
// 3D's within the 25 % of LongAgreesWithExplicit3dOnTheReducedReference, quasi-static this time.
// Not asserted, and open: the derived lower bound of the tip ratio, 1/2 (measured 0.16 here).
TEST(MpmParting, LongQuasiStaticCutsShareTheShaftsFrictionAndTheAxisCutKeepsLessAtTheTip) {
  struct Means {
    double axial = 0, tip = 0, shaft = 0, lateral = 0, shaftVar = 0;
  };
  const auto placements = [](const std::string& cut) {
    Means m;
    double shafts[4];
    for (int k = 0; k < 4; ++k) {
      Scenario sc = scenario::readFile(kReduced);
      sc.model.mpm.grid_spacing = 0.75e-3;
      sc.model.mpm.particle_spacing = 0.375e-3;
      sc.model.mpm.mass_scaling = 1e2;
      sc.model.mpm.cut = cut;
      sc.model.mpm.threads = 1;  // beside another test in CI: two threads each would oversubscribe the cores
      sc.insertion.entry_offset = k * 0.375e-3 / 4.0;
      sc.output.html = false;
      const MemorySink r = runInMemory(sc);
      m.axial += meanForce(r, 6e-3, 8e-3) / 4.0;
      m.tip += meanForce(r, 6e-3, 8e-3, "force_tip") / 4.0;
      m.lateral += meanForce(r, 6e-3, 8e-3, "force_lateral") / 4.0;
      shafts[k] = meanForce(r, 6e-3, 8e-3, "force_shaft");
      m.shaft += shafts[k] / 4.0;
    }
    for (const double f : shafts) m.shaftVar += (f - m.shaft) * (f - m.shaft) / (3.0 * 4.0);  // squared standard error
    return m;
  };
  const Means axis = placements("axis"), edges = placements("edges");
  const double explicitAxial = meanForce(runReducedExplicit(0.5e-3), 6e-3, 8e-3);
  EXPECT_LT(std::abs(axis.shaft - edges.shaft), 0.25 * axis.shaft)
      << "shaft: axis " << axis.shaft * 1e3 << " +- " << std::sqrt(axis.shaftVar) * 1e3 << " mN, edges "
      << edges.shaft * 1e3 << " +- " << std::sqrt(edges.shaftVar) * 1e3 << " mN";
  EXPECT_LT(axis.tip, edges.tip) << "tip: axis " << axis.tip * 1e3 << " mN, edges " << edges.tip * 1e3 << " mN";
  EXPECT_LT(edges.lateral, 0.0) << "the edges cut's lateral force " << edges.lateral * 1e3 << " mN";
  EXPECT_LT(std::abs(axis.axial - explicitAxial), 0.25 * explicitAxial)
      << "axial: mpm quasi-static " << axis.axial * 1e3 << " mN, explicit 3D " << explicitAxial * 1e3 << " mN";
}

// The reduced local model with its entry at 0 and 0.2 mm, half a point spacing: the peak axial
// force. Tolerance: the shift moves each lip's point columns against the needle's outline by up
// to d_p / 2; CFEMP resolves the outline within the eq 22 gap of a point's centre, so a lip's
// opening, and the wall pressure with it, is uncertain by about d_p / (4 R) = 0.4 / (4 x 0.44) =
// 23 %. One velocity field across the path (parting: none, the algorithm before the cut): 1.30 N
// at 0 mm and 6.19 N at 0.2 mm (4.7x, the full local model's 15.7 / 8.26 / 3.25 N); the parting
// contact: 0.149 and 0.148 N.
TEST(MpmParting, LongEntryShiftOfHalfAPointSpacingKeepsThePeakForce) {
  const auto run = [](const std::string& offset) {
    return runInMemory(scenario::readText(reducedLocalModel(offset), "reduced_local_model.yaml"));
  };
  const double at0 = peakForce(run("0 mm")), shifted = peakForce(run("0.2 mm"));
  EXPECT_GT(at0, 0.0);
  EXPECT_LT(std::abs(shifted - at0), 0.23 * at0) << "peak " << at0 << " N at entry 0, " << shifted << " N at 0.2 mm";
}
