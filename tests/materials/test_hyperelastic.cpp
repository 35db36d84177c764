// Constitutive library: each test fails if the physics is wrong.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <cmath>

#include "needlesim/core/error.hpp"
#include "needlesim/materials/homogeneous.hpp"
#include "needlesim/materials/hyperelastic.hpp"

using namespace needlesim::materials;

namespace {

// One material per law, with parameters of soft tissue (Pa).
std::vector<Hyperelastic> allLaws(double K = 2e5) {
  std::vector<Hyperelastic> v;
  Hyperelastic h;
  h.bulk = K;
  h.kind = LawKind::Linear;
  h.E = 30.74e3;
  h.nu = 0.422;
  v.push_back(h);
  h.kind = LawKind::NeoHookean;
  h.C10 = 3.6e3;
  v.push_back(h);
  h.kind = LawKind::MooneyRivlin;
  h.C10 = 2.0e3;
  h.C01 = 1.5e3;
  v.push_back(h);
  h.kind = LawKind::Yeoh;
  h.C10 = 3.0e3;
  h.C20 = 1.2e3;
  h.C30 = 0.4e3;
  v.push_back(h);
  h.kind = LawKind::Ogden;
  h.ogdenMu = {4.0e3, -1.0e3};
  h.ogdenAlpha = {3.5, -2.0};
  v.push_back(h);
  h.ogdenMu = {6.0e3};
  h.ogdenAlpha = {2.0};
  v.push_back(h);
  h.kind = LawKind::Fung;
  h.mu = 5.0e3;
  h.gamma = 1.8;
  v.push_back(h);
  for (auto& m : v) m.validate();
  return v;
}

Mat3 someF() {
  Mat3 F;
  F << 1.12, 0.08, -0.05, 0.03, 0.91, 0.11, -0.07, 0.02, 1.04;
  return F;
}

Mat3 rotation(double a, const Eigen::Vector3d& axis) {
  return Eigen::AngleAxisd(a, axis.normalized()).toRotationMatrix();
}

// S as a function of C only: build F = sqrt(C) (the right stretch).
Mat3 pk2OfC(const Hyperelastic& m, const Mat3& C) {
  Eigen::SelfAdjointEigenSolver<Mat3> es(C);
  return evaluate(m, es.operatorSqrt(), false).S;
}

}  // namespace

TEST(Hyperelastic, StressIsZeroAtIdentity) {
  for (const auto& m : allLaws()) {
    auto s = evaluate(m, Mat3::Identity());
    EXPECT_NEAR(s.energy, 0.0, 1e-9) << lawName(m.kind);
    EXPECT_LT(s.S.norm(), 1e-9) << lawName(m.kind);
    EXPECT_LT(s.sigma.norm(), 1e-9) << lawName(m.kind);
    auto s2 = evaluatePlaneStrain(m, Mat2::Identity());
    EXPECT_LT(s2.S.norm(), 1e-9) << lawName(m.kind);
  }
}

// The consistent tangent equals the central finite difference of S with respect
// to E = (C - I)/2. Step h = 1e-6 in strain: truncation O(h^2 W''') ~ 1e-12 relative,
// round-off ~ 1e-16 |S| / h ~ 1e-10 relative; tolerance 1e-6 of the tangent norm.
TEST(Hyperelastic, TangentMatchesFiniteDifferences3D) {
  const double h = 1e-6;
  for (const auto& m : allLaws()) {
    for (double scale : {0.0, 1.0, 2.5}) {  // identity, moderate and large deformation
      Mat3 F = Mat3::Identity() + scale * (someF() - Mat3::Identity());
      Mat3 C = F.transpose() * F;
      auto s = evaluate(m, F);
      Eigen::Matrix<double, 6, 6> fd;
      for (int J = 0; J < 6; ++J) {
        int k = kVoigt3[J][0], l = kVoigt3[J][1];
        // engineering strain increment gamma_J = h: dE_kl = dE_lk = h (normal) or h/2 (shear)
        Mat3 dC = Mat3::Zero();
        double dE = (k == l) ? h : 0.5 * h;
        dC(k, l) += 2.0 * dE;
        if (k != l) dC(l, k) += 2.0 * dE;
        Mat3 Sp = pk2OfC(m, C + dC), Sm = pk2OfC(m, C - dC);
        for (int I = 0; I < 6; ++I)
          fd(I, J) = (Sp(kVoigt3[I][0], kVoigt3[I][1]) - Sm(kVoigt3[I][0], kVoigt3[I][1])) / (2 * h);
      }
      EXPECT_LT((fd - s.tangent).norm(), 1e-6 * s.tangent.norm())
          << lawName(m.kind) << " scale " << scale << "\nAD\n" << s.tangent << "\nFD\n" << fd;
      EXPECT_LT((s.tangent - s.tangent.transpose()).norm(), 1e-10 * s.tangent.norm());
    }
  }
}

TEST(Hyperelastic, TangentMatchesFiniteDifferencesPlaneStrain) {
  const double h = 1e-6;
  Mat2 F;
  F << 1.15, 0.1, -0.06, 0.88;
  for (const auto& m : allLaws()) {
    auto s = evaluatePlaneStrain(m, F);
    Mat2 C = F.transpose() * F;
    Eigen::Matrix3d fd;
    for (int J = 0; J < 3; ++J) {
      int k = kVoigt2[J][0], l = kVoigt2[J][1];
      Mat2 dC = Mat2::Zero();
      double dE = (k == l) ? h : 0.5 * h;
      dC(k, l) += 2 * dE;
      if (k != l) dC(l, k) += 2 * dE;
      auto S2 = [&](const Mat2& Cc) {
        Eigen::SelfAdjointEigenSolver<Mat2> es(Cc);
        return evaluatePlaneStrain(m, es.operatorSqrt(), false).S;
      };
      Mat2 Sp = S2(C + dC), Sm = S2(C - dC);
      for (int I = 0; I < 3; ++I)
        fd(I, J) = (Sp(kVoigt2[I][0], kVoigt2[I][1]) - Sm(kVoigt2[I][0], kVoigt2[I][1])) / (2 * h);
    }
    EXPECT_LT((fd - s.tangent).norm(), 1e-6 * s.tangent.norm()) << lawName(m.kind);
  }
}

// S = 2 dW/dC: the stress is the derivative of the energy (FD of W, step 1e-6).
TEST(Hyperelastic, StressIsEnergyDerivative) {
  const double h = 1e-6;
  for (const auto& m : allLaws()) {
    Mat3 F = someF();
    Mat3 C = F.transpose() * F;
    Mat3 S = evaluate(m, F, false).S;
    auto W = [&](const Mat3& Cc) {
      Eigen::SelfAdjointEigenSolver<Mat3> es(Cc);
      return evaluate(m, es.operatorSqrt(), false).energy;
    };
    for (int i = 0; i < 3; ++i)
      for (int j = i; j < 3; ++j) {
        Mat3 dC = Mat3::Zero();
        dC(i, j) += h;
        if (i != j) dC(j, i) += h;
        double dW = (W(C + dC) - W(C - dC)) / (2 * h);
        // dW = sum_ij dW/dC_ij dC_ij = (i == j ? 1 : 2) * S_ij / 2
        double expected = (i == j ? 0.5 : 1.0) * S(i, j);
        EXPECT_NEAR(dW, expected, 1e-6 * S.norm() + 1e-9) << lawName(m.kind) << " " << i << j;
      }
  }
}

// Objectivity: F -> Q F leaves S unchanged and rotates sigma.
TEST(Hyperelastic, RotatingTheDeformationRotatesTheStress) {
  Mat3 Q = rotation(0.7, Eigen::Vector3d(1, 2, -0.5));
  for (const auto& m : allLaws()) {
    auto a = evaluate(m, someF(), false);
    auto b = evaluate(m, Q * someF(), false);
    EXPECT_LT((b.S - a.S).norm(), 1e-9 * a.S.norm()) << lawName(m.kind);
    EXPECT_LT((b.sigma - Q * a.sigma * Q.transpose()).norm(), 1e-9 * a.sigma.norm()) << lawName(m.kind);
    EXPECT_NEAR(b.energy, a.energy, 1e-9 * std::abs(a.energy));
  }
}

// Small-strain limit: the tangent at F = I is the isotropic linear elastic
// tensor with the law's initial shear modulus mu0 and bulk modulus K.
TEST(Hyperelastic, SmallStrainLimitIsLinearElasticity) {
  for (const auto& m : allLaws()) {
    auto s = evaluate(m, Mat3::Identity());
    double mu0 = m.initialShear();
    double K = m.kind == LawKind::Linear ? m.E / (3 * (1 - 2 * m.nu)) : m.bulk;
    double lam = K - 2.0 / 3.0 * mu0;
    Eigen::Matrix<double, 6, 6> D = Eigen::Matrix<double, 6, 6>::Zero();
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) D(i, j) = lam;
      D(i, i) += 2 * mu0;
      D(3 + i, 3 + i) = mu0;
    }
    EXPECT_LT((s.tangent - D).norm(), 1e-9 * D.norm()) << lawName(m.kind) << "\n" << s.tangent;
  }
}

// Seed 002 eq 12 (seed 004 II.A): for incompressible neo-Hookean, E = 6 C10; every
// law's incompressible uniaxial slope at lambda = 1 is 3 mu0.
TEST(Hyperelastic, IncompressibleYoungsModulusIsThreeMu0) {
  const double h = 1e-6;
  for (const auto& m : allLaws()) {
    double slope = (uniaxialCauchyIncompressible(m, 1 + h) - uniaxialCauchyIncompressible(m, 1 - h)) / (2 * h);
    EXPECT_NEAR(slope, 3 * m.initialShear(), 1e-6 * slope) << lawName(m.kind);
    if (m.kind == LawKind::NeoHookean) EXPECT_NEAR(slope, 6 * m.C10, 1e-6 * slope);
  }
}

// Seed 002 eq 10 / seed 004 eq 10: sigma_22 = 2 C10 / lambda (lambda^3 - 1).
TEST(Hyperelastic, NeoHookeanUniaxialEqualsSeed002Eq10) {
  Hyperelastic m;
  m.kind = LawKind::NeoHookean;
  m.C10 = 4.9e3;
  m.bulk = 1e6;
  for (double lam : {0.5, 0.7, 0.9, 0.99, 1.0, 1.2, 1.6}) {
    double expected = 2 * m.C10 / lam * (lam * lam * lam - 1);
    EXPECT_NEAR(uniaxialCauchyIncompressible(m, lam), expected, 1e-10 * m.C10) << lam;
  }
}

// Seed 000 eq 33: sigma = mu (lambda^2 - 1/lambda) exp(gamma (lambda^2 + 2/lambda - 3)).
TEST(Hyperelastic, FungUniaxialEqualsSeed000Eq33) {
  Hyperelastic m;
  m.kind = LawKind::Fung;
  m.mu = 2.3e3;
  m.gamma = 3.1;
  m.bulk = 1e6;
  for (double lam : {0.6, 0.72, 0.85, 0.95, 1.1, 1.3}) {
    double expected = m.mu * (lam * lam - 1 / lam) * std::exp(m.gamma * (lam * lam + 2 / lam - 3));
    EXPECT_NEAR(uniaxialCauchyIncompressible(m, lam), expected, 1e-10 * std::abs(expected) + 1e-9) << lam;
  }
}

TEST(Hyperelastic, OtherIncompressibleClosedForms) {
  auto laws = allLaws();
  for (double lam : {0.7, 1.3}) {
    const auto& mr = laws[2];  // 2 (lambda^2 - 1/lambda)(C10 + C01/lambda)
    EXPECT_NEAR(uniaxialCauchyIncompressible(mr, lam),
                2 * (lam * lam - 1 / lam) * (mr.C10 + mr.C01 / lam), 1e-9);
    const auto& og = laws[4];  // sum mu (lambda^a - lambda^-a/2)
    double s = 0;
    for (int p = 0; p < 2; ++p)
      s += og.ogdenMu[p] * (std::pow(lam, og.ogdenAlpha[p]) - std::pow(lam, -og.ogdenAlpha[p] / 2));
    EXPECT_NEAR(uniaxialCauchyIncompressible(og, lam), s, 1e-9);
    const auto& nh = laws[1];  // equibiaxial 2 C10 (l^2 - l^-4), simple shear 2 C10 gamma
    EXPECT_NEAR(equibiaxialCauchyIncompressible(nh, lam), 2 * nh.C10 * (lam * lam - std::pow(lam, -4)), 1e-9);
    EXPECT_NEAR(simpleShearIncompressible(nh, lam - 1), 2 * nh.C10 * (lam - 1), 1e-9);
    // Ogden with one term alpha = 2 is neo-Hookean with C10 = mu/2 in every mode
    Hyperelastic nh2 = nh;
    nh2.C10 = laws[5].ogdenMu[0] / 2;
    EXPECT_NEAR(simpleShearIncompressible(laws[5], 0.4), simpleShearIncompressible(nh2, 0.4), 1e-9);
    EXPECT_NEAR(equibiaxialCauchyIncompressible(laws[5], lam), equibiaxialCauchyIncompressible(nh2, lam), 1e-9);
  }
}

// A near-incompressible solid (nu = 0.4999, K/mu0 ~ 1e4) approaches the
// incompressible response; the difference is of order mu0/K.
TEST(Hyperelastic, CompressibleUniaxialApproachesIncompressible) {
  for (auto m : allLaws()) {
    if (m.kind == LawKind::Linear) continue;
    double nu = 0.4999;
    m.bulk = 2 * m.initialShear() * (1 + nu) / (3 * (1 - 2 * nu));
    for (double lam : {0.75, 1.25}) {
      auto c = uniaxialCompressible(m, lam);
      double inc = uniaxialCauchyIncompressible(m, lam);
      EXPECT_NEAR(c.cauchy, inc, 2e-3 * std::abs(inc)) << lawName(m.kind) << " " << lam;
      EXPECT_NEAR(c.lateralStretch, 1 / std::sqrt(lam), 1e-3);
      EXPECT_NEAR(simpleShearCompressible(m, 0.3), simpleShearIncompressible(m, 0.3),
                  2e-3 * std::abs(simpleShearIncompressible(m, 0.3)));
    }
  }
  // linear small strain: uniaxial slope E, lateral contraction nu
  auto lin = allLaws()[0];
  auto c = uniaxialCompressible(lin, 1 + 1e-6);
  EXPECT_NEAR(c.cauchy / 1e-6, lin.E, 1e-4 * lin.E);
  EXPECT_NEAR((1 - c.lateralStretch) / 1e-6, lin.nu, 1e-4);
}

TEST(Hyperelastic, InvertedElementIsASolverErrorNotNaN) {
  Mat3 F = Mat3::Identity();
  F(0, 0) = -0.1;
  EXPECT_THROW(evaluate(allLaws()[1], F), needlesim::SolverError);
}

TEST(Hyperelastic, SpecValidationNamesTheParameter) {
  MaterialSpec s;
  s.law = "neo-hookean";
  s.params = {{"C10", -5.0}};
  try {
    Hyperelastic::fromSpec(s);
    FAIL();
  } catch (const needlesim::Error& e) {
    EXPECT_NE(std::string(e.what()).find("C10"), std::string::npos);
  }
  s.params = {{"C10", 1e3}, {"nu", 0.5}};
  EXPECT_THROW(Hyperelastic::fromSpec(s), needlesim::Error);
  s.law = "hookean";
  EXPECT_THROW(Hyperelastic::fromSpec(s), needlesim::Error);
  s.law = "ogden";
  s.params = {{"mu1", 1e3}, {"alpha1", -2.0}};
  EXPECT_THROW(Hyperelastic::fromSpec(s), needlesim::Error);
  // K from nu: K = 2 mu0 (1 + nu) / (3 (1 - 2 nu))
  s.law = "fung";
  s.params = {{"mu", 1e3}, {"gamma", 2.0}, {"nu", 0.45}};
  auto h = Hyperelastic::fromSpec(s);
  EXPECT_NEAR(h.bulk, 2e3 * 1.45 / (3 * 0.1), 1e-6);
}

TEST(Hyperelastic, EveryLibraryMaterialBuilds) {
  for (const auto& [name, spec] : materialLibrary()) {
    auto h = Hyperelastic::fromSpec(spec);
    EXPECT_NEAR(h.initialShear(), smallStrainModuli(spec).shear, 1e-9 * h.initialShear()) << name;
  }
}

// Near-incompressible (nu = 0.499, K / mu0 ~ 500): the tangent still matches
// finite differences; the volumetric stiffness dominates, so the tolerance is
// relative to the full tangent norm as above.
TEST(Hyperelastic, TangentAtNu0499) {
  const double h = 1e-7;
  for (auto m : allLaws()) {
    if (m.kind == LawKind::Linear) continue;
    const double nu = 0.499;
    m.bulk = 2 * m.initialShear() * (1 + nu) / (3 * (1 - 2 * nu));
    Mat3 F = someF();
    Mat3 C = F.transpose() * F;
    auto s = evaluate(m, F);
    for (int J = 0; J < 6; ++J) {
      int k = kVoigt3[J][0], l = kVoigt3[J][1];
      Mat3 dC = Mat3::Zero();
      double dE = (k == l) ? h : 0.5 * h;
      dC(k, l) += 2 * dE;
      if (k != l) dC(l, k) += 2 * dE;
      Mat3 dS = (pk2OfC(m, C + dC) - pk2OfC(m, C - dC)) / (2 * h);
      for (int I = 0; I < 6; ++I)
        EXPECT_NEAR(dS(kVoigt3[I][0], kVoigt3[I][1]), s.tangent(I, J), 1e-6 * s.tangent.norm())
            << lawName(m.kind) << " " << I << J;
    }
  }
}

// Plane strain: in-plane rotations rotate the in-plane stress, sigma_33 is invariant.
TEST(Hyperelastic, PlaneStrainObjectivity) {
  Mat2 F;
  F << 1.15, 0.1, -0.06, 0.88;
  const double a = 0.9;
  Mat2 Q;
  Q << std::cos(a), -std::sin(a), std::sin(a), std::cos(a);
  for (const auto& m : allLaws()) {
    auto s = evaluatePlaneStrain(m, F, false), r = evaluatePlaneStrain(m, Q * F, false);
    EXPECT_LT((r.sigma - Q * s.sigma * Q.transpose()).norm(), 1e-9 * s.sigma.norm()) << lawName(m.kind);
    EXPECT_NEAR(r.sigma33, s.sigma33, 1e-9 * s.sigma.norm());
    EXPECT_LT((r.S - s.S).norm(), 1e-9 * s.S.norm());
  }
}
