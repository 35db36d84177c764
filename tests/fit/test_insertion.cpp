// Insertion-log analyses on synthetic logs with known answers.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "needlesim/core/error.hpp"
#include "needlesim/fit/insertion.hpp"

using namespace needlesim::fit;

namespace {
// A log through a block of thickness L: stiffness ramp to a puncture at zp
// (peak Fp), then F = Fcut + (C + b v) z while the tip is inside, then
// (C + b v) L once it has exited.
InsertionLog syntheticLog(double v, double C, double b, double Fcut, double L, double zp, double Fp,
                          double zEnd, double noise, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> N(0.0, 1.0);
  InsertionLog log;
  log.file = "log.csv";
  log.speed = v;
  const int n = 600;
  for (int i = 0; i <= n; ++i) {
    double z = zEnd * i / n;
    double f;
    if (z <= zp)
      f = Fp * z / zp;
    else if (z <= L)
      f = Fcut + (C + b * v) * z;
    else
      f = (C + b * v) * L;
    log.depth.push_back(z);
    log.force.push_back(f + noise * N(rng));
    log.lines.push_back(i + 2);
  }
  return log;
}
}  // namespace

TEST(Insertion, PunctureDepthAndForce) {
  auto log = syntheticLog(0.003, 3.8, 285, 0.05, 0.055, 0.008, 0.4, 0.07, 0.0, 1);
  Puncture p = detectPuncture(log);
  ASSERT_TRUE(p.found);
  const double dz = 0.07 / 600;  // one sample
  EXPECT_NEAR(p.depth, 0.008, dz);
  EXPECT_NEAR(p.force, 0.4 * p.depth / 0.008, 1e-12);
  EXPECT_NEAR(p.force, 0.4, 0.4 * dz / 0.008);
  EXPECT_NEAR(p.stiffness, 0.4 / 0.008, 1e-6);
  EXPECT_GT(p.drop, 0.3);
}

// G_c A = F_cut L1 exactly when friction grows linearly with depth (seed 002
// eqs 14-19 with F2'(L) = F2 L / L2).
TEST(Insertion, RuptureToughnessClosedForm) {
  const double C = 3.0, b = 300, v = 0.00125, Fcut = 0.3, L = 0.102, d = 0.71e-3;
  auto log = syntheticLog(v, C, b, Fcut, L, 0.004, 0.6, 0.13, 0.0, 2);
  ToughnessOptions o;
  o.diameter = d;
  o.shaftLength = L;
  auto r = ruptureToughness(log, o);
  double A = std::numbers::pi / 4 * d * d;
  EXPECT_NEAR(r.windowStart, 0.004, 0.13 / 600);
  EXPECT_NEAR(r.F2, (C + b * v) * L, 1e-9);
  EXPECT_NEAR(r.Gc, Fcut * r.L1 / A, 1e-3 * Fcut * r.L1 / A);
  // seed 004 IV.A: t_c from G_c
  EXPECT_NEAR(cohesiveStrength(r.Gc, 0.71e-3), 2 * r.Gc / 0.71e-3, 1e-6);
  // literal reading of eq 12 differs by k L1^2 / 2 / A
  o.literalEq12 = true;
  o.windowStart = 0.01;
  auto lit = ruptureToughness(log, o);
  double k = (C + b * v);
  EXPECT_NEAR(lit.Gft, k * lit.L1 * lit.L1 / A, 1e-6 * lit.Gft);
}

// Four speeds (seed 003: 2.5, 3.33, 5, 10 mm/s), C = 3.791 N/m, b = 285.053 N s/m^2
// (the seed's averages), cutting per speed from Table 5.2, 5 mN noise.
TEST(Insertion, MultiSpeedFrictionRecoversParameters) {
  const double C = 3.791, b = 285.053, L = 0.055;
  const double v[4] = {0.0025, 0.00333, 0.005, 0.01}, cut[4] = {0.042, 0.044, 0.055, 0.057};
  std::vector<InsertionLog> logs;
  for (int i = 0; i < 4; ++i) logs.push_back(syntheticLog(v[i], C, b, cut[i], L, 0.006, 0.25, 0.07, 0.005, 10 + i));
  FrictionFit f = fitFrictionCutting(logs, L, CuttingModel::PerSpeed);
  EXPECT_NEAR(f.C, C, 4 * f.seC);
  EXPECT_NEAR(f.b, b, 4 * f.seB);
  EXPECT_NEAR(f.C, C, 0.05 * C);
  EXPECT_NEAR(f.b, b, 0.05 * b);
  for (int i = 0; i < 4; ++i) EXPECT_NEAR(f.cutting[i], cut[i], 4 * f.seCutting[i] + 1e-4);
  EXPECT_LT(f.rmse, 0.0055);
  // one speed only: cannot separate C and b
  EXPECT_THROW(fitFrictionCutting({logs[0]}, L), needlesim::InputError);
}

TEST(FitInsertion, FrictionFromLogsRequiresTheBlockThickness) {
  InsertionLog a, b;
  a.file = b.file = "x.csv";
  a.speed = 2.5e-3;
  b.speed = 5e-3;
  for (int i = 0; i < 100; ++i) {
    a.depth.push_back(i * 1e-3);
    b.depth.push_back(i * 1e-3);
    a.force.push_back(0.01 * i);
    b.force.push_back(0.012 * i);
    a.lines.push_back(i + 2);
    b.lines.push_back(i + 2);
  }
  try {
    fitFrictionCutting({a, b}, 0.0);
    FAIL() << "no error without --thickness";
  } catch (const needlesim::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("--thickness"), std::string::npos);
  }
}
