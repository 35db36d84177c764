// 3D zero-thickness cohesive quadrilaterals (cohesive_surface.cpp,
// docs/models/cohesive.md "Interface (3D)", docs/validation/cohesive.md
// "Verification"): two hex blocks pulled apart (mode I and mode II) dissipate
// G_c x area; a 3D insertion with the cohesive seam dissipates G_c x cracked area.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "needlesim/core/error.hpp"
#include "needlesim/engines/explicit/cohesive.hpp"
#include "needlesim/engines/explicit/cohesive_wedge.hpp"
#include "needlesim/engines/explicit/solver.hpp"
#include "needlesim/engines/memory_sink.hpp"
#include "needlesim/scenario/reader.hpp"

using namespace needlesim;
using namespace needlesim::explicit_fe;

namespace {

materials::MaterialSpec linearSpec(double E) {
  materials::MaterialSpec ms;
  ms.law = "linear";
  ms.params = {{"E", E}, {"nu", 0.3}};
  ms.density = 1000;
  return ms;
}

struct Pull3d {
  double area = 0, tributary = 0, dissipated = 0, balance = 0, cohWork = 0, stored = 0;
  int open = 0, pairs = 0, quads = 0;
};

// Two L x L x L blocks (2x2 or 3x3 hexes in plane, non-uniform spacing) on either side of y = 0,
// the bottom face fixed, the top face moved along `dir` at speed v until 1.5 delta_f.
Pull3d pullApart(const Eigen::Vector3d& dir, const CohesiveLaw& l) {
  const double L = 0.01;
  Mesh m = structuredBlock({0, 0.3 * L, 0.65 * L, L}, {-L, 0, L}, {0, 0.5 * L, L}, ElementType::Hex8);
  auto pairs = splitSeam(m, 0.0, -1.0, 1.0, 1.0);
  ExplicitSolver s(m, {Material::fromSpec(linearSpec(1e6))});
  s.setCohesive(CohesiveInterface::surface3D(m, pairs, {l}, Eigen::Vector3d::UnitY(), Eigen::Vector3d::UnitX()));
  Pull3d r;
  r.area = L * L;
  r.pairs = s.cohesive()->pairs();
  r.quads = s.cohesive()->quads();
  for (int p = 0; p < r.pairs; ++p) r.tributary += s.cohesive()->tributaryLength(p);
  const int bot = s.addGroup();
  std::vector<int> top(3);
  for (int i = 0; i < 3; ++i) top[i] = s.addGroup();
  for (int n = 0; n < m.nodes(); ++n)
    for (int i = 0; i < 3; ++i) {
      if (m.coord(n, 1) < -L + 1e-12) s.addDof(bot, n, i);
      if (m.coord(n, 1) > L - 1e-12) s.addDof(top[i], n, i);
    }
  const double v = 0.02;
  for (int i = 0; i < 3; ++i) s.setGroupVelocity(top[i], v * dir[i]);
  const double df = std::max(l.deltaF(), 2 * l.G2() / l.sc());
  s.advanceTo(1.5 * df / v);
  const auto& E = s.energies();
  r.open = s.cohesive()->fullyDamaged();
  r.dissipated = E.cohesiveDissipated;
  r.balance = E.balance();
  r.cohWork = E.cohesiveWork;
  r.stored = E.cohesiveStored;
  return r;
}

CohesiveLaw law3d() {
  CohesiveLaw l;
  l.stiffness = 1e9;
  l.strength = 1e4;
  l.energy = 2.0;
  l.shearEnergy = 4.0;
  return l;
}

}  // namespace

TEST(Cohesive3d, QuadsAndTributaryAreasCoverTheSeam) {
  const double L = 0.01;
  Mesh m = structuredBlock({0, 0.3 * L, 0.65 * L, L}, {-L, 0, L}, {0, 0.5 * L, L}, ElementType::Hex8);
  auto pairs = splitSeam(m, 0.0, -1.0, 1.0, 1.0);
  ASSERT_EQ(pairs.size(), 12u);
  auto c = CohesiveInterface::surface3D(m, pairs, {law3d()}, Eigen::Vector3d::UnitY(), Eigen::Vector3d::UnitX());
  EXPECT_EQ(c.quads(), 6);
  double A = 0;
  for (int p = 0; p < c.pairs(); ++p) A += c.tributaryLength(p);
  EXPECT_NEAR(A, L * L, 1e-15);
  // corner pair (0,0,0): a quarter of the 0.3 L x 0.5 L face
  EXPECT_NEAR(c.tributaryLength(0), 0.25 * 0.3 * L * 0.5 * L, 1e-15);
  // a 2D (quad4) mesh is refused
  Mesh m2 = structuredBlock({0, L}, {-L, 0, L}, ElementType::Quad4);
  auto p2 = splitSeam(m2, 0.0, 0.0, L);
  EXPECT_THROW(CohesiveInterface::surface3D(m2, p2, {law3d()}, Eigen::Vector3d::UnitY(), Eigen::Vector3d::UnitX()),
               Error);
}

// Mode I: the top block pulled straight up; the whole interface opens and dissipates G_Ic x area.
TEST(Cohesive3d, TwoBlocksModeIDissipateGcTimesArea) {
  const auto l = law3d();
  const auto r = pullApart(Eigen::Vector3d::UnitY(), l);
  std::printf("3D mode I: D = %.6g J, G_c A = %.6g J (%.3f %%), open %d/%d, balance %.2g J\n", r.dissipated,
              l.energy * r.area, 100 * (r.dissipated / (l.energy * r.area) - 1), r.open, r.pairs, r.balance);
  EXPECT_EQ(r.open, r.pairs);
  // trapezoidal dissipation increments over ~1e4 steps: well within 1 %
  EXPECT_NEAR(r.dissipated, l.energy * r.area, 0.01 * l.energy * r.area);
  EXPECT_NEAR(r.balance, 0.0, 1e-9 * l.energy * r.area);
  EXPECT_NEAR(r.cohWork, r.stored + r.dissipated, 0.01 * l.energy * r.area);
}

// Mode II: the top block slid along z (and x): isotropic shear, G_IIc x area.
TEST(Cohesive3d, TwoBlocksModeIIDissipateGIIcTimesArea) {
  const auto l = law3d();
  const auto r = pullApart(Eigen::Vector3d(0.6, 0.0, 0.8), l);
  std::printf("3D mode II: D = %.6g J, G_IIc A = %.6g J (%.3f %%), open %d/%d\n", r.dissipated,
              l.shearEnergy * r.area, 100 * (r.dissipated / (l.shearEnergy * r.area) - 1), r.open, r.pairs);
  EXPECT_EQ(r.open, r.pairs);
  EXPECT_NEAR(r.dissipated, l.shearEnergy * r.area, 0.01 * l.shearEnergy * r.area);
  EXPECT_NEAR(r.balance, 0.0, 1e-9 * l.shearEnergy * r.area);
}

// Engine level, 3D (model.explicit.cohesive on a hex8 mesh): a 2 mm conical needle (45 deg half
// angle) into soft tissue with the cohesive quadrilaterals on the seam plane through the axis. The
// cone wedges the pairs it meets apart along the seam normal (cohesive_wedge.hpp); behind it they
// open fully. Each pair dissipates at most G_c (G_IIc = G_c), so D lies between G_c x fully damaged
// area and G_c x (fully + partly damaged area).
namespace {
std::string insertion3dYaml(const std::string& extra = "") {
  return R"(
name: cohesive_insertion_3d
tissue:
  block: {length: 6 mm, width: 6 mm, height: 6 mm}
  material: {law: neo-hookean, C10: 3.6 kPa, nu: 0.45, density: 1000 kg/m^3}
  friction: {coefficient: 0.3}
  interaction: {toughness: 2 J/m^2}
needle: {outer_diameter: 2 mm, length: 30 mm, bevel_angle: 45 deg, tip: conical, youngs_modulus: 200 GPa}
insertion:
  entry_angle: 90 deg
  start_depth: -0.5 mm
  profile:
    - insert: {to: 2.5 mm, speed: 10 mm/s}
model:
  engine: explicit
  explicit:
    dimension: 3d
    element: hex8
    element_size: 0.5 mm
    max_element_size: 2 mm
    core_width: 3 mm
    mass_scaling: 15
    hourglass: 3
)" + extra + R"(    tip_friction: 0
    cohesive: {enable: true, strength: 20 kPa}
output: {interval: 10 ms}
)";
}
}  // namespace

TEST(Cohesive3dInsertion, ConeWedgesSeamOpenAndDissipationMatchesGcTimesCrackedArea) {
  MemorySink r = runInMemory(scenario::readText(insertion3dYaml(), "<cohesive3d>"));
  const double Gc = 2.0, h = 0.5e-3;
  const double A = r.results.at("cracked_area").value, D = r.results.at("cohesive_dissipation").value;
  const double Ap = r.results.at("process_zone_area").value, GcA = r.results.at("fracture_energy_of_crack").value;
  const double ext = r.results.at("cracked_length").value;
  std::printf("3D cohesive insertion: cracked area %.4g mm^2 (extent %.3f mm), process zone %.4g mm^2, D = %.4g J, "
              "G_c A = %.4g J (%+.2f %%), G_c (A + A_p) = %.4g J, balance %.2g, peak force %.4g N, needle energy "
              "balance error %.3g\n",
              A * 1e6, ext * 1e3, Ap * 1e6, D, GcA, 100 * (D / GcA - 1), Gc * (A + Ap), 
              r.results.at("energy_balance_error").value, r.results.at("peak_force").value,
              r.results.at("needle_energy_balance_error").value);
  EXPECT_NEAR(GcA, Gc * A, 1e-12);
  // the crack follows the cone: open behind it (apex at 2.5 mm, cone 1 mm long, +- one element)
  EXPECT_GT(ext, 2.5e-3 - 1e-3 - 2 * h);
  // the pairs inside the needle's section (|z| < r: 3 columns of 0.5 mm = 2r - h) are open behind the
  // front, bar the last row
  EXPECT_GT(A, (2e-3 - h) * (ext - h));
  // exact dissipation per pair (closed form, cohesive.cpp): G_c A <= D <= G_c (A + A_p)
  EXPECT_GE(D, GcA * (1 - 1e-9));
  EXPECT_LE(D, Gc * (A + Ap) * (1 + 1e-9));
  EXPECT_LE(r.results.at("cohesive_pair_dissipation_max").value, 1.0 + 1e-9);
  EXPECT_LT(r.results.at("energy_balance_error").value, 1e-6);
}

// The same cut with the conservative penalty (fixed_contact_stiffness): the needle work balances kinetic +
// internal + cohesive + friction + penalty energy: measured 1.4 % in 3D (the 3D cone wedge leaves the part of the
// gap's gradient along the seam off the lips; 37 % with k following the step).
TEST(Cohesive3dInsertion, NeedleEnergyBalanceWithFixedContactStiffness) {
  MemorySink r = runInMemory(scenario::readText(insertion3dYaml("    fixed_contact_stiffness: true\n"), "<c3dk>"));
  std::printf("3D cohesive insertion (fixed k): needle work %.4g J, friction %.3g J, cohesive D %.3g J, cracked %.3g "
              "mm^2, needle balance error %.3g\n",
              r.results.at("needle_work").value, r.results.at("friction_dissipation").value,
              r.results.at("cohesive_dissipation").value, r.results.at("cracked_area").value * 1e6,
              r.results.at("needle_energy_balance_error").value);
  EXPECT_GT(r.results.at("cracked_area").value, 2e-6);
  EXPECT_LT(r.results.at("needle_energy_balance_error").value, 0.05);  // the defaults' tolerance
  EXPECT_LT(r.results.at("energy_balance_error").value, 1e-9);
}

// The same cut on the default contact settings (each node's penalty kept over its contact episode,
// solver.cpp episodeStiffness): the needle work balances within 5 %. What is left is the cone wedge's
// force, which leaves the along-seam part b/c of the gap's gradient off the lips (docs/models/cohesive.md):
// not the gradient of 1/2 k gap^2, so its work differs from the stored energy's change (measured 1.8 %;
// 37 % with k following the shrinking step).
TEST(Cohesive3dInsertion, NeedleEnergyBalanceOnDefaults) {
  MemorySink r = runInMemory(scenario::readText(insertion3dYaml(), "<c3d>"));
  std::printf("3D cohesive insertion (defaults): needle work %.4g J, friction %.3g J, cohesive D %.3g J, cracked %.3g "
              "mm^2, needle balance error %.3g\n",
              r.results.at("needle_work").value, r.results.at("friction_dissipation").value,
              r.results.at("cohesive_dissipation").value, r.results.at("cracked_area").value * 1e6,
              r.results.at("needle_energy_balance_error").value);
  EXPECT_GT(r.results.at("cracked_area").value, 2e-6);
  EXPECT_LT(r.results.at("needle_energy_balance_error").value, 0.05);
  EXPECT_LT(r.results.at("energy_balance_error").value, 1e-9);
}

// Engine level, 3D bevel (45 deg, 2 mm): the cohesive seam plane runs through the needle axis
// (docs/models/cohesive.md "3D bevel"); the wall-side lip is pushed down ahead of the point by the
// virtual chisel and the bevel-side lip up by the face, to +-sqrt(R^2 - b^2) around the shaft. The
// cracked area grows with depth and D lies between G_c x fully damaged area and G_c x (fully + partly
// damaged area) (exact per-pair dissipation, cohesive.cpp). Each lip's gap is a continuous function of
// its reference axial station and along-seam coordinate and of its current coordinate across the seam,
// along which it is pushed (cohesive_wedge.cpp): a conservative contact, so the needle's work balances
// the energy it delivers. Asserted below 1 %, above the 2D bevel cuts' 0.02-0.74 % on the defaults;
// measured 0.10 % at 2.5 mm and 0.03 % at 4 mm (645 % and 676 % with the gap at the current along-seam
// coordinate and the hold switched on at the chisel's reach: the gap jumps, docs/models/cohesive.md).
namespace {
std::string bevel3dYaml(const std::string& depth) {
  std::string y = insertion3dYaml();
  const auto tip = y.find("tip: conical");
  y.replace(tip, 12, "tip: bevel");
  const auto to = y.find("to: 2.5 mm");
  y.replace(to, 10, "to: " + depth);
  // the wall-side chisel reaches R / tan(30 deg) = 1.7 mm ahead of the point: start clear of it
  const auto st = y.find("start_depth: -0.5 mm");
  y.replace(st, 20, "start_depth: -1.8 mm");
  // the 0.2 explicit-range penalty on every node, lips included (with the default 10 and lips at 0.3
  // the wall-side lip penetrates 0.51-0.58 mm > the 0.5 mm tolerance at 1.4-2.2 mm; measured after the
  // merge of the end-of-step contact, docs/models/cohesive.md "3D bevel")
  const auto hg = y.find("    hourglass: 3\n");
  y.insert(hg, "    contact_penalty: 0.3\n");
  return y;
}
}  // namespace

TEST(Cohesive3dInsertion, BevelOpensSeamThroughAxisAndDissipationMatchesGcTimesCrackedArea) {
  const double Gc = 2.0, R = 1e-3;
  double prevA = 0.0;
  for (const char* depth : {"2.5 mm", "4 mm"}) {
    MemorySink r = runInMemory(scenario::readText(bevel3dYaml(depth), "<cohesive3d-bevel>"));
    const double A = r.results.at("cracked_area").value, D = r.results.at("cohesive_dissipation").value;
    const double Ap = r.results.at("process_zone_area").value, GcA = r.results.at("fracture_energy_of_crack").value;
    const double ext = r.results.at("cracked_length").value;
    std::printf("3D bevel cohesive insertion to %s: cracked area %.4g mm^2 (extent %.3f mm), process zone %.4g mm^2, "
                "D = %.4g J, G_c A = %.4g J (%+.2f %%), peak force %.4g N, balance %.2g, needle balance %.3g\n",
                depth, A * 1e6, ext * 1e3, Ap * 1e6, D, GcA, 100 * (D / GcA - 1), r.results.at("peak_force").value,
                r.results.at("energy_balance_error").value, r.results.at("needle_energy_balance_error").value);
    // open over most of the needle's width (2R less one 0.5 mm column) along the extent
    EXPECT_GT(A, R * ext);
    EXPECT_GT(A, prevA + R * 1e-3);  // 1.5 mm deeper opens at least 1 mm^2 more
    prevA = A;
    EXPECT_GE(D, GcA * (1 - 1e-9));
    EXPECT_LE(D, Gc * (A + Ap) * (1 + 1e-9));
    EXPECT_LE(r.results.at("cohesive_pair_dissipation_max").value, 1.0 + 1e-9);
    EXPECT_LT(r.results.at("energy_balance_error").value, 1e-6);
    EXPECT_LT(r.results.at("needle_energy_balance_error").value, 0.01);
  }
}

namespace {

using LipRule = bool (*)(const needle::NeedleShape&, const needle::NeedlePose&, const Eigen::Vector3d&, int,
                         needle::NeedleHit&, double&);

// A 45 deg bevel of radius 1 mm, tip at the origin, axis x, bevel side y (b along z).
needle::NeedleShape bevel45() {
  needle::NeedleShape sh;
  sh.radius = 1e-3;
  sh.length = 0.03;
  sh.tipAngle = 45.0 * M_PI / 180.0;
  sh.tip = TipType::Bevel;
  return sh;
}

// A 3D bevel's lip rule as a potential: at a fixed node, each lip's gap is continuous along the axis, and the
// needle's work per unit lateral force, sum of gap x axial reaction over the advance, is the change of gap^2 / 2:
// the contact energy of a lip changes only by the work the needle does on it. Sampled over lips above, on and
// below the axis plane and the sharp point's plane, across the chord, from ahead of the chisel's reach to behind
// the heel.
void expectLipRuleIsAPotential(LipRule rule, const char* name) {
  const needle::NeedleShape sh = bevel45();
  const needle::NeedlePose pose;
  const double R = sh.radius, h = 1e-7, slopeMax = std::max(std::tan(sh.tipAngle), std::tan(needle::kLipRampAngle));
  struct Gap {
    double g = 0.0, slope = 0.0;
  };
  auto gapAt = [&](double s, double a, double b, int side) {
    needle::NeedleHit hit;
    double slope = 0.0;
    const bool in = rule(sh, pose, Eigen::Vector3d(s, a, b), side, hit, slope);
    return in ? Gap{hit.depth, slope} : Gap{};
  };
  double worstJump = 0.0, worstWork = 0.0;
  for (int side : {-1, 1})
    for (double b : {0.0, 0.3 * R, 0.7 * R, 0.95 * R, 0.999 * R})
      for (double a : {-1.2 * R, -R, -0.5 * R, -0.1 * R, 0.0, 0.1 * R, 0.5 * R, 1.2 * R}) {
        // the tip advances by h per sample: the node's axial station s from the tip falls from 4 mm to -4 mm
        double work = 0.0, prev = gapAt(4e-3, a, b, side).g;
        for (double s = 4e-3 - h; s > -4e-3; s -= h) {
          const Gap mid = gapAt(s + 0.5 * h, a, b, side), now = gapAt(s, a, b, side);
          worstJump = std::max(worstJump, std::abs(now.g - prev) - slopeMax * h);
          work += mid.g * mid.slope * h;
          prev = now.g;
        }
        const double g0 = gapAt(4e-3, a, b, side).g, g1 = prev;
        worstWork = std::max(worstWork, std::abs(work - 0.5 * (g1 * g1 - g0 * g0)));
      }
  std::printf("%s lip gaps: largest step beyond the slope %.3g m, largest work defect %.3g m^2 (R^2 = %.3g)\n", name,
              worstJump, worstWork, R * R);
  EXPECT_LT(worstJump, 1e-12) << name;
  // the midpoint sum's error: ~ gap x (change of slope) x h at each kink of the gap (face, hold, outline)
  EXPECT_LT(worstWork, 8 * R * slopeMax * h) << name;
}

}  // namespace

// The seam through the axis (the cohesive seam): no jump where the hold begins, s = w / tan(beta), for a lip
// dragged below the plane.
TEST(Cohesive3dWedge, BevelLipGapsAreContinuousAndTheNeedleReactionIsTheirSlope) {
  expectLipRuleIsAPotential(&bevelWedge3D, "3D bevel, seam through the axis");
}

// The node-release slit through the sharp point: no jump at the point, where the face takes over from the ramp
// ahead of it.
TEST(Cohesive3dWedge, SlitLipGapsAreContinuousAndTheNeedleReactionIsTheirSlope) {
  expectLipRuleIsAPotential(&bevelSlitWedge3D, "3D bevel, slit through the sharp point");
}

// The slit through the sharp point opens where the bevel cuts: behind the heel a lip node on the slit's plane
// (a = -R) at b across it is pushed, on the bevel side, to the upper outline sqrt(R^2 - b^2) (a full 2R on the
// sharp point's line) and, on the wall side, not at all (the lower outline -sqrt(R^2 - b^2) lies above it); under
// the face the bevel-side lip sits on the face continued across the chord, -R - s tan(alpha).
TEST(Cohesive3dWedge, SlitOpensTheBevelSideLipByTheWholeNeedleAndLeavesTheWallSide) {
  const needle::NeedleShape sh = bevel45();
  const needle::NeedlePose pose;
  const double R = sh.radius, heel = -2.0 * R / std::tan(sh.tipAngle);
  for (double b : {0.0, 0.4 * R, 0.9 * R}) {
    const double w = std::sqrt(R * R - b * b);
    needle::NeedleHit hit;
    double slope = 0.0;
    ASSERT_TRUE(bevelSlitWedge3D(sh, pose, Eigen::Vector3d(heel - 1e-3, -R, b), 1, hit, slope)) << b;
    EXPECT_NEAR(hit.depth, R + w, 1e-12 * R) << b;
    EXPECT_NEAR(hit.normal.y(), 1.0, 1e-12);
    EXPECT_EQ(slope, 0.0);
    EXPECT_FALSE(bevelSlitWedge3D(sh, pose, Eigen::Vector3d(heel - 1e-3, -R, b), -1, hit, slope)) << b;
    // under the face, a quarter of the way to the heel: lifted by a quarter of 2R, reaction tan(alpha)
    ASSERT_TRUE(bevelSlitWedge3D(sh, pose, Eigen::Vector3d(0.25 * heel, -R, b), 1, hit, slope)) << b;
    EXPECT_NEAR(hit.depth, 0.5 * R, 1e-12 * R) << b;
    EXPECT_NEAR(slope, std::tan(sh.tipAngle), 1e-12);
  }
}
