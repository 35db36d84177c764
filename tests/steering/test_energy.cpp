// Energy-based incremental model, seed 002 section 4 (eqs 27-49), with the choices
// of docs/models/bevel-tip-energy.md.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <numbers>
#include <vector>

#include "needlesim/engines/steering/curvature_fit.hpp"
#include "needlesim/engines/steering/energy_model.hpp"
#include "needlesim/engines/steering/table2.hpp"

using namespace needlesim::steering;
constexpr double deg = std::numbers::pi / 180.0;

namespace {
EnergyParams fig22(double d, double beta_ratio) {
  // seed 002 section 5.3 / Fig 22: alpha = 45 deg, P_input = 0.5 mN, 150 mm, porcine gel
  EnergyParams p;
  p.diameter = d;
  p.alpha = 45 * deg;
  p.beta_ratio = beta_ratio;
  p.K_T = 10.46e3;
  p.P_input = 0.5e-3;
  return p;
}
// the literal eq 45 frame (two Hermite pieces over the whole inserted length) [choice 9]
EnergyParams entry(EnergyParams p) {
  p.frame = EnergyFrame::Entry;
  return p;
}
double curvatureOf(const EnergyParams& p) {
  std::vector<Eigen::Vector3d> path;
  runEnergyModel(p, &path);
  const double rho = fitCircle(path).radius;
  return std::isfinite(rho) ? 1.0 / rho : 0.0;
}
}  // namespace

TEST(EnergyModel, SymmetricTipGoesStraight) {
  // beta = 0: the roller is along the axis, no transverse reaction, no deflection at all
  EnergyParams p = fig22(0.46e-3, 0.0);
  std::vector<Eigen::Vector3d> path;
  const EnergyResult r = runEnergyModel(p, &path);
  EXPECT_EQ(r.final_deflection, 0.0);
  for (const auto& x : path) EXPECT_EQ(x.y(), 0.0);
  EXPECT_GE(r.final_length, 0.15 - 1e-3);
}

TEST(EnergyModelEntry, DeflectionRisesWithCutAngle) {
  // Fig 22: a smaller beta/alpha gives a smaller final tip deflection
  double prev = 0;
  for (double br : {0.25, 0.5, 0.75, 1.0}) {
    const double d = std::abs(runEnergyModel(entry(fig22(0.4e-3, br))).final_deflection);
    EXPECT_GT(d, prev * 1.2) << br;
    prev = d;
  }
}

TEST(EnergyModelEntry, BevelFlipReversesTheDeflection) {
  EnergyParams p = entry(fig22(0.4e-3, 0.5));
  const double d0 = runEnergyModel(p).final_deflection;
  p.flip_depths = {0.075};
  const double d1 = runEnergyModel(p).final_deflection;
  EXPECT_LT(std::abs(d1), 0.5 * std::abs(d0));
}

TEST(EnergyModel, LargerInputForceMeansFewerIncrements) {
  // Fig 21(c): the input force sets the increment size
  EnergyParams p = fig22(0.4e-3, 0.5);
  const int n1 = runEnergyModel(p).increments;
  p.P_input *= 4;
  const int n4 = runEnergyModel(p).increments;
  EXPECT_LT(n4, n1);
}

TEST(EnergyModel, SubStepOneReactionBalancesTheInputForce) {
  // eq 27 with the roller: H = -P_input whenever the advance is not capped
  EnergyParams p = fig22(0.4e-3, 0.5);
  p.insertion = 0.01;
  std::vector<EnergyIncrement> inc;
  runEnergyModel(p, nullptr, 1e-3, &inc);
  ASSERT_GT(inc.size(), 10u);
  int checked = 0;
  for (size_t k = 0; k + 1 < inc.size(); ++k) {
    if (inc[k + 1].length - inc[k].length >= 0.999 * p.max_step) continue;  // capped advance
    EXPECT_NEAR(inc[k].H, -p.P_input, 1e-9 * p.P_input);
    ++checked;
  }
  EXPECT_GT(checked, 10);
}

TEST(EnergyModel, DeflectionRisesWithSmallerDiameter) {
  // Fig 22: a thicker needle (EI ~ d^4) bends less. The default (path-window) frame gives
  // kappa ~ chi tan(beta) (K_T / 4EI)^(1/4) ~ 1/d, with the cut share chi also falling with d
  // (the tear a is the needle radius, choice 10). At beta/alpha 0.25 both 150 mm paths stay
  // below a half turn, where the final deflection rho (1 - cos(L/rho)) still rises with kappa;
  // at beta/alpha 0.5 the 0.3 mm path turns about 170 degrees, so there the test compares curvatures.
  const double thin = std::abs(runEnergyModel(fig22(0.3e-3, 0.25)).final_deflection);
  const double thick = std::abs(runEnergyModel(fig22(0.6e-3, 0.25)).final_deflection);
  EXPECT_GT(thin, 1.2 * thick);
  const double k_thin = curvatureOf(fig22(0.3e-3, 0.5)), k_thick = curvatureOf(fig22(0.6e-3, 0.5));
  // 1/d alone gives 2; the cut share chi (0.87 against 0.74) adds about 18 %
  EXPECT_GT(k_thin, 2.0 * k_thick);
  EXPECT_LT(k_thin, 2.8 * k_thick);
}

TEST(EnergyModel, RadiusFallsWithInputForce) {
  // Fig 21(a): a larger input force steers more, and the radius levels off for large forces;
  // below the rupture threshold a G_f the push cannot cut sideways at all (choice 10).
  EnergyParams p = fig22(0.46e-3, 0.5);  // section 5.3: 0.46 mm, 31.89 deg, beta/alpha 0.5
  p.alpha = 31.89 * deg;
  const double a = 0.23e-3, threshold = a * p.fracture_energy;
  std::vector<double> rho;
  for (double P : {0.2e-3, 0.5e-3, 1e-3, 5e-3}) {
    p.P_input = P;
    const double k = curvatureOf(p);
    rho.push_back(1.0 / k);
    // closed form of choice 10: the curvature is chi = 1 - a G_f / P_input times that of a
    // rupture-free push (whose curvature does not depend on P_input)
    EnergyParams free = p;
    free.fracture_energy = 0;
    EXPECT_NEAR(k / curvatureOf(free), 1 - threshold / P, 0.01) << P;
  }
  for (size_t i = 1; i < rho.size(); ++i) EXPECT_LT(rho[i], rho[i - 1]);
  // "for a larger total force the value and the variation of the radius are smaller"
  EXPECT_LT((rho[2] - rho[3]) / rho[3], 0.5 * (rho[0] - rho[1]) / rho[1]);
  p.P_input = 0.9 * threshold;
  EXPECT_EQ(runEnergyModel(p).final_deflection, 0.0);
}

TEST(EnergyModel, FrictionRaisesTheRadiusMostForTheThickestNeedle) {
  // Fig 23: 0-50 % of the input work dissipated by friction, 45 deg, 0.5 mN, d 0.3/0.4/0.5 mm.
  // The friction takes (1 - f) of the push to the tip; the rupture share a G_f / P_eff grows,
  // and grows most for the thick needle (a = radius). The paper: +39.5 % for 0.5 mm at 50 %;
  // G_f = 0.44 J/m^2 is inferred from that one number (docs), so only the ordering and the
  // monotonic rise are independent checks; the 0.5 mm value checks the inference.
  std::vector<double> rise;
  for (double d : {0.3e-3, 0.4e-3, 0.5e-3}) {
    EnergyParams p = fig22(d, 0.5);
    double prev = 0;
    double rho0 = 0;
    for (double f : {0.0, 0.25, 0.5}) {
      p.friction_fraction = f;
      const double rho = 1.0 / curvatureOf(p);
      EXPECT_GT(rho, prev) << d << " " << f;
      if (f == 0.0) rho0 = rho;
      prev = rho;
    }
    rise.push_back(prev / rho0 - 1);
  }
  EXPECT_LT(rise[0], rise[1]);
  EXPECT_LT(rise[1], rise[2]);
  EXPECT_NEAR(rise[2], 0.395, 0.03);
}

TEST(EnergyModel, SymmetricTipLimitIsContinuous) {
  // the straight path of a symmetric tip is the beta -> 0 limit, not a special case:
  // the curvature goes to zero linearly in tan(beta)
  const double k1 = curvatureOf(fig22(0.46e-3, 0.02)), k2 = curvatureOf(fig22(0.46e-3, 0.04));
  EXPECT_GT(k1, 0.0);
  EXPECT_NEAR(k2 / k1, std::tan(0.04 * 45 * deg) / std::tan(0.02 * 45 * deg), 0.03);
  EXPECT_EQ(curvatureOf(fig22(0.46e-3, 0.0)), 0.0);
  EXPECT_EQ(curvatureOf(entry(fig22(0.46e-3, 0.0))), 0.0);
}

// [choice 9] path-attached Ritz window: the tip turns by the same angle per unit
// advance, so the curvature is a property of the needle and tissue.
namespace {
EnergyParams windowed(EnergyParams p) {
  p.frame = EnergyFrame::PathWindow;
  return p;
}
double wholeCurvature(const EnergyParams& p) {
  std::vector<Eigen::Vector3d> path;
  runEnergyModel(p, &path);
  return 1.0 / fitCircle(path).radius;
}
}  // namespace

TEST(EnergyModelWindow, CurvatureRisesWithSmallerDiameter) {
  // Fig 22 / Table 2: thinner needles bend more (EI ~ d^4; the window model gives
  // kappa ~ tan(beta) (K_T/EI)^(1/4) ~ 1/d). beta/alpha 0.25 keeps both paths below a half turn.
  const double thin = wholeCurvature(windowed(fig22(0.3e-3, 0.25)));
  const double thick = wholeCurvature(windowed(fig22(0.6e-3, 0.25)));
  EXPECT_GT(thin, 1.6 * thick);
  EXPECT_LT(thin, 2.4 * thick);
  const double d_thin = std::abs(runEnergyModel(windowed(fig22(0.3e-3, 0.25))).final_deflection);
  const double d_thick = std::abs(runEnergyModel(windowed(fig22(0.6e-3, 0.25))).final_deflection);
  EXPECT_GT(d_thin, 1.2 * d_thick);
}

TEST(EnergyModelWindow, CurvatureRisesWithCutAngle) {
  double prev = 0;
  for (double br : {0.25, 0.5, 0.75, 1.0}) {
    const double k = wholeCurvature(windowed(fig22(0.4e-3, br)));
    EXPECT_GT(k, prev * 1.2) << br;
    prev = k;
  }
}

TEST(EnergyModelWindow, PathIsNearlyCircular) {
  // seed 002 section 5.1: the radius stays nearly constant over the three 50 mm sections
  for (const auto& c : table2Cases()) {
    EnergyParams p = windowed(fig22(c.diameter, c.beta_tip));
    p.alpha = c.alpha;
    p.K_T = c.K_T;
    p.P_input = c.P_input;
    std::vector<Eigen::Vector3d> path;
    runEnergyModel(p, &path);
    const SectionRadii s = sectionRadii(path);
    for (double rho : s.rho) EXPECT_NEAR(rho / s.whole, 1.0, 0.3) << c.gel << " " << c.diameter;
  }
}

TEST(EnergyModelWindow, KeepsTheSubStepBalancesAndTheSymmetricTip) {
  EnergyParams p = windowed(fig22(0.4e-3, 0.5));
  p.insertion = 0.01;
  std::vector<EnergyIncrement> inc;
  runEnergyModel(p, nullptr, 1e-3, &inc);
  ASSERT_GT(inc.size(), 10u);
  for (const auto& e : inc) EXPECT_NEAR(e.H, -p.P_input, 1e-9 * p.P_input);  // eq 27, uncapped
  const int n1 = static_cast<int>(inc.size());
  p.P_input *= 4;
  EXPECT_LT(runEnergyModel(p).increments, n1);  // Fig 21(c)
  p = windowed(fig22(0.4e-3, 0.0));
  std::vector<Eigen::Vector3d> path;
  EXPECT_EQ(runEnergyModel(p, &path).final_deflection, 0.0);
  for (const auto& x : path) EXPECT_EQ(x.y(), 0.0);
}

TEST(EnergyModelWindow, BevelFlipTurnsThePathBack) {
  // a flip halfway makes an S: the tip ends parallel to the axis, the deflection about halves
  EnergyParams p = windowed(fig22(0.4e-3, 0.25));
  std::vector<EnergyIncrement> a, b;
  const double d0 = runEnergyModel(p, nullptr, 1e-3, &a).final_deflection;
  p.flip_depths = {0.075};
  const double d1 = runEnergyModel(p, nullptr, 1e-3, &b).final_deflection;
  EXPECT_LT(d0, 0.0);  // same side as the eq 45 reading (the engine maps y = v)
  EXPECT_LT(std::abs(d1), 0.6 * std::abs(d0));
  EXPECT_GT(std::abs(d1), 0.3 * std::abs(d0));
  EXPECT_LT(std::abs(b.back().phi), 0.05 * std::abs(a.back().phi));
}

TEST(EnergyModel, RejectsNonPhysicalInput) {
  EnergyParams p = fig22(0.4e-3, 1.2);
  EXPECT_THROW(runEnergyModel(p), std::invalid_argument);
  p = fig22(0.4e-3, 0.5);
  p.P_input = 0;
  EXPECT_THROW(runEnergyModel(p), std::invalid_argument);
}

TEST(Table2, AllTwelveCasesRunForBothMechanicsModels) {
  for (const auto& c : table2Cases()) {
    for (const char* m : {"energy", "beam-foundation"}) {
      const Table2Row r = runTable2Case(c, m);
      EXPECT_TRUE(std::isfinite(r.deflection_pred)) << c.gel << m;
      EXPECT_GT(r.increments, 0);
    }
    // the measured deflection is derived from the measured radius over a 150 mm arc
    const Table2Row r = runTable2Case(c, "beam-foundation");
    EXPECT_NEAR(r.deflection_exp, c.rho_exp * (1 - std::cos(0.15 / c.rho_exp)), 1e-15);
  }
}

TEST(Table2, CalibratedCutAngleReproducesTheMeasuredRadius) {
  // one beta/alpha fitted to one needle: the bisection must land on rho_exp (both models are
  // monotone in beta/alpha, in opposite directions)
  const auto& c = table2Cases()[8];  // gel C, 0.54 mm
  for (const char* m : {"energy", "beam-foundation"}) {
    const double br = calibrateBetaRatio(c, m);
    EXPECT_GT(br, 0.01) << m;
    EXPECT_LT(br, 1.0) << m;
    EXPECT_NEAR(runTable2Case(c, m, br).rho_pred, c.rho_exp, 1e-3 * c.rho_exp) << m;
  }
}

TEST(Table2, EnergyModelPredictsTheOtherDiametersOfAGel) {
  // Leave-two-out: beta/alpha fitted per gel on one needle predicts the two other needles.
  // A model whose diameter dependence is right must beat the constant-curvature (kinematic)
  // baseline, which predicts the calibration radius for every needle of the gel. The paper's
  // own fitted model deviated 4.1-32.9 % (seed 002 section 5.2).
  for (int cal = 0; cal < 3; ++cal) {
    double e_energy = 0, e_kin = 0, worst = 0;
    for (const auto& pr : table2CrossValidation("energy", cal)) {
      e_energy += std::abs(pr.error) / 8;
      worst = std::max(worst, std::abs(pr.error));
    }
    for (const auto& pr : table2CrossValidation("kinematic", cal)) e_kin += std::abs(pr.error) / 8;
    EXPECT_LT(e_energy, 0.15) << cal;
    EXPECT_LT(worst, 0.329) << cal;
    EXPECT_LT(e_energy, 0.8 * e_kin) << cal;
  }
}

TEST(Table2, RadiusProportionalBaselineScalesTheCalibrationRadius) {
  // the second baseline (issue 21): rho = c d with c = rho_exp / d of the calibration needle, so a
  // prediction is rho_exp(cal) d / d(cal); seed 002 Table 2's gel C 0.36 -> 0.54 mm:
  // 206.7 x 0.54 / 0.36 = 310.05 mm against the measured 240.0 mm (+29.2 %)
  const auto& cases = table2Cases();
  for (int cal = 0; cal < 3; ++cal)
    for (const auto& pr : table2CrossValidation("radius-proportional", cal)) {
      const Table2Case& c = cases[pr.case_index];
      const Table2Case& k = cases[pr.calibration_case];
      EXPECT_NEAR(pr.rho_pred, k.rho_exp * c.diameter / k.diameter, 1e-12);
      EXPECT_NEAR(pr.error, pr.rho_pred / c.rho_exp - 1, 1e-12);
    }
  const auto p = table2CrossValidation("radius-proportional", 0);
  EXPECT_NEAR(p[5].rho_pred, 0.31005, 1e-6);  // gel C 0.54 mm from 0.36 mm
  EXPECT_NEAR(p[5].error, 0.2919, 1e-3);
  EXPECT_THROW(runTable2Case(cases[0], "no-such-model"), std::invalid_argument);
}

TEST(EnergyModel, WorkBalanceSetsTheCutShare) {
  // choice 10 bookkeeping: per unit advance the input work P_input is split into friction
  // f P_input, rupture a G_f and the sideways cut; the reported works must reproduce chi
  EnergyParams p = fig22(0.46e-3, 0.5);
  p.friction_fraction = 0.3;
  p.fracture_energy = 1.0;
  const EnergyResult r = runEnergyModel(p);
  const double a = 0.23e-3, P_eff = 0.7 * p.P_input;
  EXPECT_NEAR(r.W_friction / r.W_input, 0.3, 1e-12);
  EXPECT_NEAR(r.W_R / r.W_input, a * p.fracture_energy / p.P_input, 1e-12);
  EXPECT_NEAR(r.cut_share, 1 - a * p.fracture_energy / P_eff, 1e-12);
  EXPECT_NEAR(r.cut_share, 1 - r.W_R / (r.W_input - r.W_friction), 1e-12);
  // the works are those of the whole advance from l_0 to the end
  EXPECT_NEAR(r.W_input, p.P_input * (r.final_length - p.initial_length), 0.01 * r.W_input);
  p.fracture_energy = -1;
  EXPECT_THROW(runEnergyModel(p), std::invalid_argument);
}
