// Cohesive zone (docs/models/cohesive.md, docs/validation/cohesive.md):
// bilinear traction-separation law (seed 001 eqs 5-6, seed 004 eq 14), line
// interface on seam pairs, and the mode-I double cantilever beam against beam
// theory and LEFM.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "needlesim/core/error.hpp"
#include "needlesim/engines/explicit/cohesive.hpp"
#include "needlesim/engines/explicit/solver.hpp"

using namespace needlesim;
using namespace needlesim::explicit_fe;

namespace {

CohesiveLaw law1() {
  CohesiveLaw l;
  l.stiffness = 1e9;  // Pa/m
  l.strength = 1e4;   // Pa -> delta_0 = 1e-5 m
  l.energy = 5.0;     // J/m^2 -> delta_f = 1e-3 m
  l.shearStrength = 2e4;
  l.shearEnergy = 12.0;
  return l;
}

// Work of the traction along a straight monotonic path (dn, ds) = s (cn, cs), s from 0 to smax.
double pathWork(const CohesiveLaw& l, double cn, double cs, double smax, CohesiveState& st, int n = 200000) {
  double W = 0, tnP = 0, tsP = 0;
  for (int i = 1; i <= n; ++i) {
    const double s = smax * i / n, ds = smax / n;
    auto t = cohesiveUpdate(l, s * cn, s * cs, st);
    W += 0.5 * (t.tn + tnP) * cn * ds + 0.5 * (t.ts + tsP) * cs * ds;
    tnP = t.tn, tsP = t.ts;
  }
  return W;
}

}  // namespace

TEST(CohesiveLaw, ModeIAreaEqualsFractureEnergy) {
  const auto l = law1();
  CohesiveState st;
  const double W = pathWork(l, 1.0, 0.0, 1.2 * l.deltaF(), st);
  // area under the bilinear triangle = G_c (seed 001 eq 6): trapezoid error O(1/n^2)
  EXPECT_NEAR(W, l.energy, 1e-4 * l.energy);
  EXPECT_DOUBLE_EQ(st.damage, 1.0);
  EXPECT_NEAR(st.dissipated, l.energy, 1e-4 * l.energy);  // all of it dissipated, nothing stored
  // peak traction t_c at delta_0
  CohesiveState s2;
  EXPECT_NEAR(cohesiveUpdate(l, l.delta0(), 0, s2).tn, l.strength, 1e-9 * l.strength);
}

TEST(CohesiveLaw, ModeIIAndMixedModeFollowLinearEnergyCriterion) {
  const auto l = law1();
  {
    CohesiveState st;
    const double W = pathWork(l, 0.0, 1.0, 1.2 * 2 * l.shearEnergy / l.sc(), st);
    EXPECT_NEAR(W, l.shearEnergy, 1e-4 * l.shearEnergy);
  }
  for (double beta : {0.5, 1.0, 3.0}) {
    CohesiveState st;
    const double c = 1 / std::sqrt(1 + beta * beta);
    double d0, df;
    cohesiveMixedMode(l, c, beta * c, d0, df);
    // energy split: G_I : G_II = 1 : beta^2 along a proportional path
    double GI = 0, GII = 0, tnP = 0, tsP = 0;
    const int n = 200000;
    for (int i = 1; i <= n; ++i) {
      const double s = 1.1 * df * i / n, ds = 1.1 * df / n;
      auto t = cohesiveUpdate(l, s * c, s * beta * c, st);
      GI += 0.5 * (t.tn + tnP) * c * ds;
      GII += 0.5 * (t.ts + tsP) * beta * c * ds;
      tnP = t.tn, tsP = t.ts;
    }
    EXPECT_NEAR(GI / l.energy + GII / l.shearEnergy, 1.0, 1e-3) << "beta " << beta;
    EXPECT_DOUBLE_EQ(st.damage, 1.0);
    // quadratic initiation at d0
    CohesiveState s0;
    auto t0 = cohesiveUpdate(l, d0 * c, d0 * beta * c, s0);
    EXPECT_NEAR(std::pow(t0.tn / l.strength, 2) + std::pow(t0.ts / l.sc(), 2), 1.0, 1e-9);
    EXPECT_NEAR(s0.damage, 0.0, 1e-12);
  }
}

TEST(CohesiveLaw, UnloadingFollowsDamagedSecantAndNeverHeals) {
  const auto l = law1();
  CohesiveState st;
  const double dmax = 0.4 * l.deltaF();
  pathWork(l, 1, 0, dmax, st, 2000);
  const double d = st.damage, tPeak = cohesiveUpdate(l, dmax, 0, st).tn;
  EXPECT_GT(d, 0.5);
  EXPECT_LT(d, 1.0);
  // on the softening line
  EXPECT_NEAR(tPeak, l.strength * (l.deltaF() - dmax) / (l.deltaF() - l.delta0()), 1e-9 * l.strength);
  const double Dmax = st.dissipated;
  for (double f : {0.75, 0.5, 0.1, 0.0, 0.5, 1.0}) {  // unload to zero and reload to dmax
    auto t = cohesiveUpdate(l, f * dmax, 0, st);
    EXPECT_NEAR(t.tn, f * tPeak, 1e-9 * l.strength) << f;  // secant (1-d) K delta, through the origin
    EXPECT_DOUBLE_EQ(st.damage, d);                      // no healing, no new damage
    EXPECT_DOUBLE_EQ(st.dissipated, Dmax);
  }
  // compression: undamaged penalty (faces do not interpenetrate)
  auto tc = cohesiveUpdate(l, -1e-6, 0, st);
  EXPECT_NEAR(tc.tn, -l.stiffness * 1e-6, 1e-9);
  EXPECT_DOUBLE_EQ(st.damage, d);
  // reloading beyond dmax continues on the softening line
  auto t2 = cohesiveUpdate(l, 0.6 * l.deltaF(), 0, st);
  EXPECT_NEAR(t2.tn, l.strength * (l.deltaF() - 0.6 * l.deltaF()) / (l.deltaF() - l.delta0()), 1e-9 * l.strength);
  // fully damaged: open in tension and shear, still closed in compression
  cohesiveUpdate(l, 2 * l.deltaF(), 0, st);
  EXPECT_EQ(st.damage, 1.0);
  EXPECT_EQ(cohesiveUpdate(l, 0.5 * l.deltaF(), 0.1 * l.deltaF(), st).tn, 0.0);
  EXPECT_EQ(cohesiveUpdate(l, 0.5 * l.deltaF(), 0.1 * l.deltaF(), st).ts, 0.0);
  EXPECT_LT(cohesiveUpdate(l, -1e-6, 0, st).tn, 0.0);
}

TEST(CohesiveLaw, Seed004Parameterisation) {
  // seed 004 IV-A: K = E (unit constitutive thickness), t_c = 2 G_c / delta_c; Table I plastisol (soft):
  // G_c = 39.3 kJ/m^2, delta_c = 0.71 mm -> t_c = 110.7 MPa (the paper's 110.6 MPa column)
  auto l = CohesiveLaw::fromCriticalSeparation(21.5e3, 1.0, 39.3e3, 0.71e-3);
  EXPECT_NEAR(l.strength, 110.7e6, 0.1e6);
  EXPECT_NEAR(l.deltaF(), 0.71e-3, 1e-12);
  // K = E/T0 with T0 = 1 m (or 1 mm) reaches t_c only at t_c/K >> delta_c: no bilinear triangle
  EXPECT_THROW(l.validate(), Error);
  // it needs T0 < delta_c E / t_c = 0.14 um (K > 1.6e11 Pa/m)
  EXPECT_NO_THROW(CohesiveLaw::fromCriticalSeparation(21.5e3, 1e-8, 39.3e3, 0.71e-3).validate());
}

// Two unit squares (quad4) stacked, cohesive interface between them, the top pulled up slowly:
// the dissipated energy is G_c times the interface length (x 1 m) once fully open.
TEST(CohesiveInterface, TwoBlocksSeparateWithGcTimesLength) {
  const double L = 0.01;
  Mesh m = structuredBlock({0, 0.5 * L, L}, {-L, 0, L}, ElementType::Quad4);
  auto pairs = splitSeam(m, 0.0, 0.0, L);
  ASSERT_EQ(pairs.size(), 3u);
  materials::MaterialSpec ms;
  ms.law = "linear";
  ms.params = {{"E", 1e6}, {"nu", 0.3}};
  ms.density = 1000;
  ExplicitSolver s(m, {Material::fromSpec(ms)});
  CohesiveLaw l;
  l.stiffness = 1e9;
  l.strength = 1e4;
  l.energy = 2.0;
  s.setCohesive(CohesiveInterface(m.X, pairs, {l}));
  EXPECT_NEAR(s.cohesive()->tributaryLength(0) + s.cohesive()->tributaryLength(1) + s.cohesive()->tributaryLength(2), L,
              1e-15);
  const int bot = s.addGroup(), top = s.addGroup();
  for (int n = 0; n < m.nodes(); ++n) {
    if (m.coord(n, 1) < -L + 1e-12) s.addDof(bot, n, 0), s.addDof(bot, n, 1);
    if (m.coord(n, 1) > L - 1e-12) s.addDof(top, n, 0), s.addDof(top, n, 1);
  }
  const double v = 0.02;  // m/s: opening 1.5 delta_f in 0.03 s
  s.setGroupVelocity(top, v);
  s.advanceTo(1.5 * l.deltaF() / v);
  const auto& E = s.energies();
  EXPECT_EQ(s.cohesive()->fullyDamaged(), 3);
  EXPECT_NEAR(E.cohesiveDissipated, l.energy * L, 0.01 * l.energy * L);
  // energy balance with the cohesive work: round-off
  EXPECT_NEAR(E.balance(), 0.0, 1e-9 * l.energy * L);
  EXPECT_NEAR(E.cohesiveWork, E.cohesiveStored + E.cohesiveDissipated, 0.01 * l.energy * L);
}
