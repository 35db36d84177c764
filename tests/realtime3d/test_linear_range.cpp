// When realtime3d's linear elasticity holds (realtime/linear_range.hpp; docs/models/realtime3d.md "When
// linear elasticity holds"): the rotation measure against closed forms, the warning, and realtime3d's
// small-strain static solution against the explicit solver's neo-Hookean finite strains on the same
// tets under a lateral load along the needle path, from small to large rotations.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <set>
#include <string>

#include "needlesim/engines/explicit/solver.hpp"
#include "needlesim/engines/memory_sink.hpp"
#include "needlesim/engines/realtime/linear_range.hpp"
#include "needlesim/engines/realtime3d/session.hpp"
#include "needlesim/scenario/reader.hpp"
#include "../support/explicit_relaxation.hpp"
#include "../support/tet_nodes.hpp"

using namespace needlesim;
using needlesim::testing::nearestNode;

namespace {

Eigen::Matrix3d rotation(double theta) { return Eigen::AngleAxisd(theta, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix(); }

// The deformation of one tetrahedron with F = I + grad u.
realtime::Deformation tetWith(const Eigen::Matrix3d& F) {
  const std::vector<double> X{0, 0, 0, 1, 0, 0, 0, 1, 0, 0.2, 0.3, 1};
  Eigen::VectorXd u(12);
  for (int n = 0; n < 4; ++n) u.segment<3>(3 * n) = (F - Eigen::Matrix3d::Identity()) * Eigen::Vector3d(X[3 * n], X[3 * n + 1], X[3 * n + 2]);
  return realtime::SimplexStrains(3, X, {0, 1, 2, 3}).measure(u);
}

struct LateralLoadCase {
  double linear = 0.0, finite = 0.0;  // mean lateral displacement of the loaded nodes (m)
  double worstNode = 0.0, largest = 0.0;  // largest |u_linear - u_finite| of a node, largest |u_finite| (m)
  realtime::Deformation linearRange;  // what the linear range check measures on realtime3d's solution
  double difference() const { return std::abs(linear - finite) / std::abs(finite); }
};

// The needle pushed sideways: a lateral (y) load `total` (N) shared by the path nodes from the entry face
// to 25 mm deep, on a 40 mm gel cube held on its four sides and far face (the engine's default supports).
LateralLoadCase lateralLoad(double total, bool finiteToo = true) {
  auto c = realtime3d::gelatinBlockConfig(9, 7, realtime3d::Backend::Direct);
  c.tissue.block.length = c.tissue.block.width = c.tissue.block.height = 0.04;
  c.tissue.block.grading = 2.0;
  realtime3d::Session rt(c);
  const auto& mesh = rt.mesh();
  std::set<int> loaded;
  for (const auto& p : rt.tissue().path())
    if (p.s <= 0.025 + 1e-9) loaded.insert(nearestNode(mesh, p.X));
  const double each = total / static_cast<double>(loaded.size());
  Eigen::VectorXd F = Eigen::VectorXd::Zero(3 * mesh.nodes());
  for (int n : loaded) F[3 * n + 1] = each;
  const Eigen::VectorXd u = rt.tissue().dynamics().staticSolve(F);
  LateralLoadCase r;
  r.linearRange = realtime::SimplexStrains(3, mesh.X, mesh.conn).measure(u);
  if (!finiteToo) return r;

  materials::MaterialSpec ms;
  ms.law = "neo-hookean";
  const double mu = c.tissue.material.E / (2.0 * (1.0 + c.tissue.material.nu));
  ms.params = {{"C10", 0.5 * mu}, {"nu", c.tissue.material.nu}};  // the same small-strain moduli
  ms.density = c.tissue.material.density;
  auto ex = needlesim::testing::relaxingExplicitBlock(mesh, c.tissue.block, ms);
  for (int n : loaded) ex->setExternalForce(n, 1, each);
  ex->advanceTo(0.4);

  for (int n : loaded) {
    r.linear += u[3 * n + 1] / static_cast<double>(loaded.size());
    r.finite += ex->displacement()[static_cast<std::size_t>(3 * n + 1)] / static_cast<double>(loaded.size());
  }
  for (int n = 0; n < mesh.nodes(); ++n) {
    Eigen::Vector3d ue, ul = u.segment<3>(3 * n);
    for (int i = 0; i < 3; ++i) ue[i] = ex->displacement()[static_cast<std::size_t>(3 * n + i)];
    r.worstNode = std::max(r.worstNode, (ul - ue).norm());
    r.largest = std::max(r.largest, ue.norm());
  }
  return r;
}

}  // namespace


// A rigid rotation by theta gives theta, and the small strain 1 - cos(theta) the linear model makes of
// it (the spurious compression the rotation bound is argued from); a pure stretch gives no rotation;
// a stretch then a rotation gives the rotation.
TEST(Realtime3dLinearRange, RotationOfThePolarDecomposition) {
  for (double theta : {1e-3, 0.2, 1.0, 2.5}) {
    const auto d = tetWith(rotation(theta));
    EXPECT_NEAR(d.max_rotation, theta, 1e-9) << theta;
    EXPECT_NEAR(d.max_strain, 1.0 - std::cos(theta), 1e-8) << theta;  // closed-form eigenvalues
    EXPECT_EQ(d.inverted, 0);
  }
  Eigen::Matrix3d U;  // symmetric, positive definite, not diagonal
  U << 1.3, 0.2, -0.1, 0.2, 0.8, 0.05, -0.1, 0.05, 1.1;
  EXPECT_NEAR(tetWith(U).max_rotation, 0.0, 1e-9);
  EXPECT_NEAR(tetWith(rotation(0.4) * U).max_rotation, 0.4, 1e-9);
  // 2D: a rigid rotation of a triangle, and a pure shear strain
  const std::vector<double> X{0, 0, 1, 0, 0.3, 1};
  const realtime::SimplexStrains tri(2, X, {0, 1, 2});
  const auto moved = [&](const Eigen::Matrix2d& F) {
    Eigen::VectorXd u(6);
    for (int n = 0; n < 3; ++n) u.segment<2>(2 * n) = (F - Eigen::Matrix2d::Identity()) * Eigen::Vector2d(X[2 * n], X[2 * n + 1]);
    return tri.measure(u);
  };
  EXPECT_NEAR(moved(Eigen::Rotation2Dd(0.7).toRotationMatrix()).max_rotation, 0.7, 1e-12);
  EXPECT_NEAR(moved((Eigen::Matrix2d() << 1.0, 0.3, 0.3, 1.0).finished()).max_rotation, 0.0, 1e-12);
}

// A rotation beyond its bound warns though the strain is small, and says it is the rotation.
TEST(Realtime3dLinearRange, RotationAloneWarns) {
  MemorySink sink;
  realtime::LinearRangeWarning w("realtime3d");
  realtime::Deformation d;
  d.max_strain = 0.05;
  d.max_rotation = 0.15;
  EXPECT_FALSE(w.check(d, 1e-3, sink));
  d.max_rotation = 0.3;
  EXPECT_TRUE(w.check(d, 2e-3, sink));
  ASSERT_EQ(sink.warnings.size(), 1u);
  EXPECT_NE(sink.warnings[0].find("rotation 0.3 rad (beyond the bound)"), std::string::npos) << sink.warnings[0];
  EXPECT_EQ(sink.warnings[0].find("0.05 (beyond"), std::string::npos) << sink.warnings[0];
  EXPECT_DOUBLE_EQ(w.worstRotation(), 0.3);
}

namespace {
// The amplitude (N) at which the linear range check first warns on realtime3d's solution: the strain is
// linear in the load, the rotation nearly so; found from a small load and refined once.
double warningLoad() {
  const auto at = [](double P) {
    const auto r = lateralLoad(P, false).linearRange;
    return P / std::max(r.max_strain / realtime::kLinearStrainBound, r.max_rotation / realtime::kLinearRotationBound);
  };
  return at(at(0.1));
}
}  // namespace

// Small loads: the two agree within 0.5% of the largest displacement (the same tets; what differs is
// the finite-strain kinematics, of the order of the strain, 1e-3 here, and the relaxation's residual).
// Just past the load where realtime3d warns, the largest nodal difference is still within the 10 % of the
// largest displacement the bound is meant to keep. The difference is first order in the load (the
// finite kinematics add terms quadratic in the displacement), so three times the load gives two to
// four times the difference: past the warning it keeps growing.
TEST(Realtime3dLinearRange, AgreesWithFiniteStrainsUntilItWarns) {
  const auto small = lateralLoad(0.01);
  EXPECT_LT(small.worstNode, 0.005 * small.largest);
  EXPECT_LT(small.linearRange.max_strain, 1e-2);

  const double P = 1.01 * warningLoad();  // just past the bound
  const auto warned = lateralLoad(P);
  MemorySink sink;
  realtime::LinearRangeWarning w("realtime3d");
  EXPECT_TRUE(w.check(warned.linearRange, 0.025, sink));
  const auto beyond = lateralLoad(3.0 * P);
  std::printf("warns at %.3g N: strain %.3f, rotation %.3f rad; node %.2f%%, mean %.2f%%; at 3x: node %.2f%%, mean %.2f%%\n", P,
              warned.linearRange.max_strain, warned.linearRange.max_rotation, 100 * warned.worstNode / warned.largest,
              100 * warned.difference(), 100 * beyond.worstNode / beyond.largest, 100 * beyond.difference());
  EXPECT_LT(warned.worstNode, 0.10 * warned.largest);
  const double growth = (beyond.worstNode / beyond.largest) / (warned.worstNode / warned.largest);
  EXPECT_GT(growth, 2.0);
  EXPECT_LT(growth, 4.0);
}

// The table of docs/models/realtime3d.md "When linear elasticity holds": the difference grows with the
// measured strain and rotation.
TEST(Realtime3dLinearRange, LongAmplitudeSweep) {
  double previous = 0.0;
  for (double P : {0.01, 0.5, 1.0, 2.0, 3.0, 5.0, 8.0}) {
    const auto r = lateralLoad(P);
    EXPECT_GT(r.worstNode / r.largest, previous);
    previous = r.worstNode / r.largest;
    std::printf("P %.3f N  lin %.3f mm  fin %.3f mm  diff %.2f%%  node %.2f%% (umax %.3f mm) strain %.3f  rot %.3f  inv %d\n", P, r.linear * 1e3,
                r.finite * 1e3, 100 * r.difference(), 100 * r.worstNode / r.largest, r.largest * 1e3, r.linearRange.max_strain, r.linearRange.max_rotation, r.linearRange.inverted);
  }
}

namespace {
// A slender gel column (60 x 10 x 10 mm) held at its far face only: the needle goes 10 mm in, then its
// base turns in the insertion plane and bends the column, whose elements rotate more than they strain.
std::string tiltedColumn(const std::string& angle) {
  return R"(
name: tilted_column
tissue:
  block: {length: 60 mm, width: 10 mm, height: 10 mm}
  material: gelatin_10wt
  puncture: {force: 0.05 N}
  cutting: {force: 0.04335 N}
  friction: {C_p: 3.791 N/m, b_p: 285.053 N s/m^2, static_band: 0.1 mm/s}
needle: {outer_diameter: 18 G, length: 100 mm, bevel_angle: 30 deg}
insertion:
  start_depth: -1 mm
  profile:
    - insert: {to: 10 mm, speed: 10 mm/s}
    - rotate: {by: )" + angle + R"(, rate: 40 deg/s, axis: in-plane}
model:
  engine: realtime3d
  time_step: 1 ms
  realtime3d: {nodes_depth: 16, nodes_lateral: 5, nodes_height: 5, refinement: 1, boundary: far-face, field_interval: 0 s}
output: {interval: 10 ms}
)";
}
int linearRangeWarnings(const MemorySink& s) {
  int n = 0;
  for (const auto& w : s.warnings) n += w.find("linear tissue model no longer holds") != std::string::npos;
  return n;
}
}  // namespace

// Turned 20 deg the column's elements rotate past the bound while their strain stays within its own:
// one warning, for the rotation; turned 5 deg they stay within both and no warning. Both runs report
// the largest strain and rotation in summary.json.
TEST(Realtime3dLinearRange, RunThatRotatesPastTheBoundWarns) {
  const MemorySink bent = runInMemory(scenario::readText(tiltedColumn("20 deg"), "<tilted column>"));
  ASSERT_EQ(linearRangeWarnings(bent), 1);
  EXPECT_GT(bent.results.at("max_tissue_rotation").value, realtime::kLinearRotationBound);
  EXPECT_LT(bent.results.at("max_tissue_strain").value, realtime::kLinearStrainBound);
  for (const auto& w : bent.warnings)
    if (w.find("linear tissue model") != std::string::npos) EXPECT_NE(w.find("rad (beyond the bound)"), std::string::npos) << w;
  const MemorySink slight = runInMemory(scenario::readText(tiltedColumn("5 deg"), "<tilted column>"));
  EXPECT_EQ(linearRangeWarnings(slight), 0);
  EXPECT_GT(slight.results.at("max_tissue_rotation").value, 0.0);
  EXPECT_LT(slight.results.at("max_tissue_rotation").value, realtime::kLinearRotationBound);
}
