// The engines' closed-form stresses (fast_stress.hpp: explicit FE and MPM;
// stress_lanes.hpp: the MPM stress update on four lanes) against the
// library's own energies: each must equal the library's stress (the exact
// derivative of law_energy.hpp by automatic differentiation) and the central
// finite difference of the library's energy, at random deformation gradients.
//
// Tolerances. Closed form vs library stress and energy, 1e-10 relative: the
// same formula evaluated in another order (invariants and AD there), so the
// difference is rounding, a few 1e-16 times the ratio of the volumetric to the
// total stress (K / mu ~ 30); 1e-10 catches any wrong term (the smallest
// term, the isochoric part near J = 1, is ~1e-2 of the total). Finite
// differences, 1e-6 relative: step h = 1e-6 on F errs by h^2 |W'''| / 6
// (~1e-12 relative for these soft laws at |F - I| < 1) plus the rounding
// eps |W| / h (~1e-10 of the stress); 1e-6 leaves four orders of margin.
#include <gtest/gtest.h>

#include <Eigen/LU>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <vector>

#include "needlesim/materials/fast_stress.hpp"
#include "needlesim/materials/hyperelastic.hpp"
#include "needlesim/materials/stress_lanes.hpp"

using namespace needlesim::materials;

namespace {

// Soft-tissue parameters (Pa).
Hyperelastic neoHookean() { return {.kind = LawKind::NeoHookean, .C10 = 3.6e3, .bulk = 1e5}; }
Hyperelastic stVenantKirchhoff() { return {.kind = LawKind::Linear, .E = 30.74e3, .nu = 0.422}; }
Hyperelastic fung() { return {.kind = LawKind::Fung, .mu = 5e3, .gamma = 2.5, .bulk = 2e5}; }

// Random deformation gradients I + A, |A_ij| <= 0.3, det F in [0.5, 1.8].
std::vector<Mat3> randomF(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-0.3, 0.3);
  std::vector<Mat3> v;
  while (static_cast<int>(v.size()) < n) {
    Mat3 F = Mat3::Identity();
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) F(i, j) += u(rng);
    const double J = F.determinant();
    if (J > 0.5 && J < 1.8) v.push_back(F);
  }
  return v;
}

// P = dW/dF by central differences of the library's energy.
Mat3 energyGradientFd(const Hyperelastic& law, const Mat3& F, double h = 1e-6) {
  Mat3 P;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      Mat3 a = F, b = F;
      a(i, j) += h;
      b(i, j) -= h;
      P(i, j) = (strainEnergy(law, a) - strainEnergy(law, b)) / (2 * h);
    }
  return P;
}

using lanes::A4;

// The lane stresses of F[0..3] (one point per lane).
struct LaneResult {
  Mat3 sigma[4];
  double W[4], wave[4];
};
LaneResult laneStress(const Hyperelastic& law, double rho0, const std::array<Mat3, 4>& F) {
  A4 Fl[9], sig[6], W, wave;
  for (int c = 0; c < 9; ++c) Fl[c] = A4{F[0](c / 3, c % 3), F[1](c / 3, c % 3), F[2](c / 3, c % 3), F[3](c / 3, c % 3)};
  lanes::hyperelasticStress4(law, rho0, Fl, sig, W, wave);
  LaneResult r;
  for (int l = 0; l < 4; ++l) {
    r.sigma[l] << sig[0][l], sig[3][l], sig[5][l], sig[3][l], sig[1][l], sig[4][l], sig[5][l], sig[4][l], sig[2][l];
    r.W[l] = W[l];
    r.wave[l] = wave[l];
  }
  return r;
}

}  // namespace

// S and W of the closed forms against the library's stress and energy, and
// P = F S against the finite difference of the library's energy.
TEST(FastStress, ClosedFormsAreTheDerivativeOfTheLibraryEnergy) {
  for (const Hyperelastic& law : {neoHookean(), stVenantKirchhoff()})
    for (const Mat3& F : randomF(20, 11)) {
      Mat3 S;
      double W;
      fastPk2(law, F, F.determinant(), S, W);
      const Stress3 ref = evaluate(law, F, false);
      EXPECT_LT((S - ref.S).norm(), 1e-10 * ref.S.norm()) << lawName(law.kind) << "\n" << F;
      EXPECT_NEAR(W, ref.energy, 1e-10 * std::abs(ref.energy)) << lawName(law.kind) << "\n" << F;
      const Mat3 P = F * S;  // first Piola-Kirchhoff, dW/dF
      EXPECT_LT((P - energyGradientFd(law, F)).norm(), 1e-6 * P.norm()) << lawName(law.kind) << "\n" << F;
    }
}

// Other laws go through the library unchanged.
TEST(FastStress, OtherLawsAreTheLibrary) {
  const Mat3 F = randomF(1, 13).front();
  const Hyperelastic law = fung();
  Mat3 S;
  double W;
  fastPk2(law, F, F.determinant(), S, W);
  const Stress3 ref = evaluate(law, F, false);
  EXPECT_EQ(S, ref.S);
  EXPECT_EQ(W, ref.energy);
}

// Four lanes, four random points each time: each lane's Cauchy stress and
// energy equal the library's and the finite difference of its energy
// (sigma = J^-1 P F^T), including lanes whose det F leaves the Taylor branch
// of J^(-1/3) (|J - 1| >= 0.05) and sets where all four are near 1.
TEST(StressLanes, MatchLibraryStressAndEnergy) {
  const std::vector<Mat3> Fs = randomF(24, 14);
  for (const Hyperelastic& law : {fung(), neoHookean()})
    for (int set = 0; set < 8; ++set) {
      std::array<Mat3, 4> F;
      for (int l = 0; l < 4; ++l) {
        F[l] = Fs[static_cast<std::size_t>((3 * set + l) % Fs.size())];
        // sets 0-3 keep the random det F; sets 4-7 bring it near 1 (the all-Taylor branch)
        if (set >= 4) F[l] *= std::cbrt((1.0 + 0.01 * (l - 1.5)) / F[l].determinant());
      }
      const LaneResult r = laneStress(law, 1000.0, F);
      for (int l = 0; l < 4; ++l) {
        const Stress3 lib = evaluate(law, F[l], false);
        const double J = F[l].determinant();
        EXPECT_LT((r.sigma[l] - lib.sigma).norm(), 1e-10 * lib.sigma.norm()) << lawName(law.kind) << " J " << J;
        EXPECT_NEAR(r.W[l], lib.energy, 1e-10 * std::abs(lib.energy)) << lawName(law.kind) << " J " << J;
        const Mat3 sigmaFd = energyGradientFd(law, F[l]) * F[l].transpose() / J;
        EXPECT_LT((r.sigma[l] - sigmaFd).norm(), 1e-6 * lib.sigma.norm()) << lawName(law.kind) << " J " << J;
      }
    }
}

// Each lane gives the stress of its own point alone (the point in all four
// lanes, as the MPM's scalar evaluateStress calls it), including an idle lane
// that repeats another point; the wave speed at F = I is sqrt((K + 4/3 mu_t) / rho0).
TEST(StressLanes, EachLaneIsItsOwnPoint) {
  Mat3 F;
  F << 1.12, 0.07, -0.03, 0.02, 0.91, 0.05, -0.04, 0.01, 1.03;
  const double J0 = F.determinant();
  for (const Hyperelastic& law : {fung(), neoHookean()})
    for (const auto& Js : {std::array<double, 4>{1.0004, 0.97, 1.03, 1.0}, std::array<double, 4>{0.6, 1.0004, 1.8, 1.8}}) {
      std::array<Mat3, 4> Fs;
      for (int l = 0; l < 4; ++l) Fs[l] = std::cbrt(Js[l] / J0) * F;
      const LaneResult r = laneStress(law, 1e4, Fs);
      for (int l = 0; l < 4; ++l) {
        const LaneResult one = laneStress(law, 1e4, {Fs[l], Fs[l], Fs[l], Fs[l]});
        EXPECT_LT((r.sigma[l] - one.sigma[0]).norm(), 1e-13 * one.sigma[0].norm()) << lawName(law.kind) << " J " << Js[l];
        EXPECT_NEAR(r.W[l], one.W[0], 1e-13 * std::abs(one.W[0])) << lawName(law.kind) << " J " << Js[l];
        EXPECT_NEAR(r.wave[l], one.wave[0], 1e-14 * one.wave[0]);
      }
    }
  const Hyperelastic nh = neoHookean();
  const LaneResult id = laneStress(nh, 1e3, {Mat3::Identity(), Mat3::Identity(), Mat3::Identity(), Mat3::Identity()});
  EXPECT_NEAR(id.wave[0], std::sqrt((nh.bulk + 4.0 / 3.0 * nh.initialShear()) / 1e3), 1e-14 * id.wave[0]);
  EXPECT_LT(id.sigma[0].norm(), 1e-10 * nh.bulk);
}

// exp on lanes against std::exp, within 2 ulp over the range the stress uses.
TEST(StressLanes, ExpMatchesStdExp) {
  double worst = 0.0;
  for (int i = 0; i <= 4000; ++i) {
    const double x = -700.0 + 0.35 * i + 1e-3 * std::sin(i);
    const A4 e = lanes::exp4(A4{x, -x, 1e-3 * x, 1e-9 * x});
    const double ref[4] = {std::exp(x), std::exp(-x), std::exp(1e-3 * x), std::exp(1e-9 * x)};
    for (int l = 0; l < 4; ++l) worst = std::max(worst, std::abs(e[l] - ref[l]) / ref[l]);
  }
  EXPECT_LT(worst, 2 * std::numeric_limits<double>::epsilon());
  std::printf("exp4 worst relative error %.2e (epsilon %.2e)\n", worst, std::numeric_limits<double>::epsilon());
}
