// Rigid flat punch indentation: the MPM engine against the explicit FE engine
// on the same problem (docs/validation/mpm.md). A linear elastic block
// 8 mm deep and 16 x 16 mm wide, base fixed, sides free, pressed by a
// frictionless flat punch of radius R = 2.5 mm. FE: the explicit engine's own
// hex8 element forces, quasi-static small-strain solve (the helper of the FE
// tests, tests/explicit/linear_static.hpp), quarter model, punch nodes r <= R
// prescribed. MPM: the punch as a blunt rigid needle pushed slowly (CFEMP
// particle-to-surface contact, eqs 22-24), stiffness F/d fitted over
// d = 0.15-0.45 mm.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>

#include "../explicit/linear_static.hpp"
#include "needlesim/engines/explicit/mesh.hpp"
#include "needlesim/engines/explicit/solver.hpp"
#include "needlesim/engines/mpm/mpm_solver.hpp"

using namespace needlesim;

namespace {

constexpr double kE = 30e3, kNu = 0.3, kR = 2.5e-3, kDepth = 8e-3, kHalf = 8e-3;

// FE punch stiffness F/d (N/m) of the quarter model, core spacing h0.
double feStiffness(double h0) {
  using namespace explicit_fe;
  const auto xs = gradedCoordinates(0, kDepth, 0, 1.5 * kR, h0, 1e-3);  // depth
  const auto ys = gradedCoordinates(0, kHalf, 0, 1.5 * kR, h0, 1e-3);
  const Mesh m = structuredBlock(xs, ys, ys, ElementType::Hex8);
  materials::MaterialSpec sp;
  sp.law = "linear";
  sp.params = {{"E", kE}, {"nu", kNu}};
  sp.density = 1000;
  ExplicitSolver s(m, {Material::fromSpec(sp)});
  auto K = linstatic::probeStiffness(s, 1e-9);
  std::vector<char> fixed(m.X.size(), 0);
  std::vector<double> u(m.X.size(), 0.0);
  const double d = 1e-5;
  std::vector<int> punch;
  for (int n = 0; n < m.nodes(); ++n) {
    const double x = m.coord(n, 0), y = m.coord(n, 1), z = m.coord(n, 2);
    if (y < 1e-12) fixed[3 * n + 1] = 1;  // symmetry planes
    if (z < 1e-12) fixed[3 * n + 2] = 1;
    if (x > kDepth - 1e-12) fixed[3 * n] = fixed[3 * n + 1] = fixed[3 * n + 2] = 1;  // base
    if (x < 1e-12 && std::hypot(y, z) <= kR * (1 + 1e-9)) {
      fixed[3 * n] = 1;
      u[3 * n] = d;
      punch.push_back(n);
    }
  }
  std::vector<double> r;
  linstatic::solveLinear(K, std::vector<double>(m.X.size(), 0.0), fixed, u, &r);
  double F = 0;
  for (int n : punch) F += r[3 * n];
  return 4 * F / d;
}

// MPM punch stiffness (N/m): least-squares slope of F(d) through the origin.
double mpmStiffness(bool cfemp) {
  using namespace mpm;
  const double h = 1e-3;
  MpmConfig cfg;
  cfg.h = h;
  cfg.origin = Vec3(-4 * h, -kHalf - 3 * h, -kHalf - 3 * h);
  cfg.cells = {static_cast<int>(kDepth / h) + 7, static_cast<int>(2 * kHalf / h) + 6,
               static_cast<int>(2 * kHalf / h) + 6};
  cfg.boxLo = Vec3(0, -1, -1);
  cfg.boxHi = Vec3(kDepth, 1, 1);
  cfg.faces = {FaceBC::Free, FaceBC::Fixed, FaceBC::Free, FaceBC::Free, FaceBC::Free, FaceBC::Free};
  cfg.threads = 1;
  cfg.massScaling = 100;
  MpmSolver s(cfg);
  MpmMaterial mat;
  mat.law.kind = materials::LawKind::Linear;
  mat.law.E = kE;
  mat.law.nu = kNu;
  mat.density = 1000;
  s.addMaterial(mat);
  s.addBlock(Vec3(0, -kHalf, -kHalf), Vec3(kDepth, kHalf, kHalf), h / 2, 0, 0);
  RigidBody n;
  n.kind = RigidBody::Kind::Needle;
  n.tip = RigidBody::Tip::Blunt;
  n.radius = kR;
  n.length = 3e-3;
  n.axis = Vec3::UnitX();
  n.point = Vec3(-0.1e-3, 0, 0);
  n.surfaceContact = cfemp;
  const double v = 0.02;
  n.velocity = Vec3(v, 0, 0);
  const int r = s.addRigid(n);
  s.finalize();
  double sfd = 0, sdd = 0;
  while (s.rigid(r).point.x() < 0.45e-3) {
    s.step();
    s.rigid(r).point.x() += v * s.lastReport().dt;
    const double d = s.rigid(r).point.x();
    if (d > 0.15e-3) {
      sfd -= s.rigidForce(r).total.x() * d;
      sdd += d * d;
    }
  }
  return sfd / sdd;
}

}  // namespace

// Measured: FE 201.9 / 210.7 N/m at core spacing R/5 / R/10 (from below, as
// the staircase punch of the FE Sneddon test; Richardson p = 1: 219.5), MPM
// CFEMP 227.9 N/m (+8 % / +4 %), MPM grid contact +55 % (its contact reaches
// every node whose support holds a touching point: a wider punch). Tolerance
// 15 %: the MPM rim is resolved to the gap d_p/2 = 0.25 mm = R/10 and the flat
// punch force grows in proportion to the radius (Sneddon), plus the FE mesh
// error (4 % between R/10 and the extrapolation).
TEST(MpmVerification, LongFlatPunchAgainstExplicitFe) {
  const double fe = feStiffness(0.25e-3), feCoarse = feStiffness(0.5e-3);
  const double cf = mpmStiffness(true), grid = mpmStiffness(false);
  const double sneddon = 2 * kR * kE / (1 - kNu * kNu);
  std::printf("punch stiffness [N/m]: FE %.4g (h0 R/10), %.4g (R/5); MPM CFEMP %.4g (%.1f %%), grid %.4g (%.1f %%); "
              "Sneddon half-space %.4g\n",
              fe, feCoarse, cf, 100 * (cf / fe - 1), grid, 100 * (grid / fe - 1), sneddon);
  EXPECT_GT(fe, feCoarse);  // the FE reference converges from below
  EXPECT_NEAR(cf / fe, 1.0, 0.15);
}
