// Cohesive seam along a user-given curved path (seam_path.hpp, docs/models/cohesive.md
// "Crack path"): a grid line split and morphed onto a sine-shaped polyline; the interface's
// tributary lengths follow the curve and pulling the blocks apart dissipates G_c x arc length.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "needlesim/core/error.hpp"
#include "needlesim/engines/explicit/cohesive.hpp"
#include "needlesim/engines/explicit/seam_path.hpp"
#include "needlesim/engines/explicit/solver.hpp"

using namespace needlesim;
using namespace needlesim::explicit_fe;

namespace {
std::vector<double> line(int n, double a, double b) {
  std::vector<double> x;
  for (int i = 0; i <= n; ++i) x.push_back(a + (b - a) * i / n);
  return x;
}
// y = A sin(pi x / L) sampled at 41 points
std::vector<Eigen::Vector2d> sinePath(double L, double A) {
  std::vector<Eigen::Vector2d> p;
  for (int i = 0; i <= 40; ++i) p.emplace_back(L * i / 40, A * std::sin(M_PI * i / 40));
  return p;
}
}  // namespace

TEST(CohesivePath, PathHeightAndFoldCheck) {
  const std::vector<Eigen::Vector2d> p = {{0, 0}, {1, 1}, {3, 0}};
  EXPECT_DOUBLE_EQ(pathHeight(p, -1), 0.0);
  EXPECT_DOUBLE_EQ(pathHeight(p, 0.5), 0.5);
  EXPECT_DOUBLE_EQ(pathHeight(p, 2.0), 0.5);
  EXPECT_DOUBLE_EQ(pathHeight(p, 9.0), 0.0);
  EXPECT_THROW(pathHeight({{0, 0}}, 0.0), Error);
  EXPECT_THROW(pathHeight({{0, 0}, {0, 1}}, 0.0), Error);
  // a path farther from the line than the band folds elements: refused
  Mesh m = structuredBlock(line(20, 0, 0.01), line(10, -0.005, 0.005), ElementType::Quad4);
  EXPECT_THROW(morphOntoPath(m, 0.0, sinePath(0.01, 5e-3), 2e-3), Error);
}

// 10 x 10 mm block, h = 0.5 mm, seam on y = 0 morphed onto y = A sin(pi x / L), A = 1 mm (band 4 mm);
// bottom face fixed, top face pulled up to 1.5 delta_f. With s_c = t_c and G_IIc = G_Ic the law's
// energy is G_c for every mode ratio, so the mixed-mode opening along the curve dissipates G_c x arc length.
TEST(CohesivePath, CurvedSeamDissipatesGcTimesArcLength) {
  const double L = 0.01, A = 1e-3;
  Mesh m = structuredBlock(line(20, 0, L), line(20, -0.005, 0.005), ElementType::Quad4);
  auto pairs = splitSeam(m, 0.0, 0.0, L);
  const auto path = sinePath(L, A);
  morphOntoPath(m, 0.0, path, 4e-3);
  for (auto [a, b] : pairs) {
    EXPECT_NEAR(m.coord(a, 1), pathHeight(path, m.coord(a, 0)), 1e-15);
    EXPECT_EQ(m.coord(a, 1), m.coord(b, 1));
  }
  CohesiveLaw l;
  l.stiffness = 1e9;
  l.strength = l.shearStrength = 1e4;
  l.energy = l.shearEnergy = 2.0;
  materials::MaterialSpec ms;
  ms.law = "linear";
  ms.params = {{"E", 1e6}, {"nu", 0.3}};
  ms.density = 1000;
  ExplicitSolver s(m, {Material::fromSpec(ms)});
  s.setCohesive(CohesiveInterface(m.X, pairs, {l}));
  // tributary lengths = length of the morphed seam polyline (nodal integration of each chord)
  double chords = 0, trib = 0;
  for (int i = 0; i + 1 < s.cohesive()->pairs(); ++i) {
    const int a = s.cohesive()->node(i, 0), b = s.cohesive()->node(i + 1, 0);
    chords += std::hypot(m.coord(b, 0) - m.coord(a, 0), m.coord(b, 1) - m.coord(a, 1));
  }
  for (int i = 0; i < s.cohesive()->pairs(); ++i) trib += s.cohesive()->tributaryLength(i);
  EXPECT_NEAR(trib, chords, 1e-15);
  // arc length of A sin(pi x/L) over [0, L]: 10.242 mm for A/L = 0.1 (midpoint quadrature)
  double arc = 0;
  for (int i = 0; i < 100000; ++i) {
    const double x = L * (i + 0.5) / 100000, dy = A * M_PI / L * std::cos(M_PI * x / L);
    arc += std::sqrt(1 + dy * dy) * L / 100000;
  }
  EXPECT_NEAR(chords, arc, 1e-3 * arc);  // 20 chords of a gentle curve
  const int bot = s.addGroup(), top = s.addGroup();
  for (int n = 0; n < m.nodes(); ++n) {
    if (m.coord(n, 1) < -0.005 + 1e-12) s.addDof(bot, n, 0), s.addDof(bot, n, 1);
    if (m.coord(n, 1) > 0.005 - 1e-12) s.addDof(top, n, 0), s.addDof(top, n, 1);
  }
  const double v = 0.02;
  s.setGroupVelocity(top, v);
  s.advanceTo(1.5 * l.deltaF() / v);
  const auto& E = s.energies();
  std::printf("curved seam: arc %.5f mm, chords %.5f mm, D = %.6g J/m vs G_c x chords %.6g (%+.3f %%), open %d/%d\n",
              arc * 1e3, chords * 1e3, E.cohesiveDissipated, l.energy * chords,
              100 * (E.cohesiveDissipated / (l.energy * chords) - 1), s.cohesive()->fullyDamaged(), s.cohesive()->pairs());
  EXPECT_EQ(s.cohesive()->fullyDamaged(), s.cohesive()->pairs());
  EXPECT_NEAR(E.cohesiveDissipated, l.energy * chords, 0.01 * l.energy * chords);
  EXPECT_NEAR(E.balance(), 0.0, 1e-9 * l.energy * chords);
}
