// Coulomb friction laws of contact/coulomb.hpp: closed-form stick and slip
// values, and every derivative against central finite differences.
//
// Tolerance of the finite differences: on a smooth branch (away from the
// kink |t| = mu N) a central difference with step h = 1e-6 x the argument
// errs by h^2 |f'''| / 6 (relative ~1e-12 here: the branches are rational of
// low degree) plus the rounding eps |f| / h (relative ~1e-10). 1e-7 relative
// is three orders above both and still catches any wrong factor or sign.
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <functional>
#include <random>

#include "needlesim/contact/coulomb.hpp"

using namespace needlesim::contact;
using Eigen::Matrix3d;
using Eigen::Vector3d;

namespace {

constexpr double kFdTol = 1e-7;

double centralDifference(const std::function<double(double)>& f, double x, double h) {
  return (f(x + h) - f(x - h)) / (2.0 * h);
}

// Central-difference Jacobian of a vector function of a 3-vector.
Matrix3d jacobianFd(const std::function<Vector3d(const Vector3d&)>& f, const Vector3d& x, double h) {
  Matrix3d J;
  for (int j = 0; j < 3; ++j) {
    Vector3d a = x, b = x;
    a[j] += h;
    b[j] -= h;
    J.col(j) = (f(a) - f(b)) / (2.0 * h);
  }
  return J;
}

}  // namespace

TEST(Coulomb, StickBelowTheLimitKeepsTheTrial) {
  // |t| = 2 N below mu N = 0.3 x 10 N = 3 N: the trial stays as it is.
  EXPECT_EQ(coulombScale(2.0, 3.0), 1.0);
  EXPECT_EQ(coulombMagnitude(2.0, 3.0), 2.0);
  const Vector3d t(1.2, -1.6, 0.0);  // |t| = 2
  EXPECT_EQ(coulombReturnMap(t, 0.3 * 10.0), t);
  // at the limit itself it still sticks; a zero trial sticks (no 0/0)
  EXPECT_EQ(coulombScale(3.0, 3.0), 1.0);
  EXPECT_EQ(coulombScale(0.0, 0.0), 1.0);
  EXPECT_EQ(coulombReturnMap(Vector3d::Zero(), 0.0), Vector3d::Zero());
}

TEST(Coulomb, SlipIsCappedAtMuNAlongTheTrial) {
  const double mu = 0.3, N = 10.0;
  EXPECT_DOUBLE_EQ(coulombScale(5.0, mu * N), 0.6);
  EXPECT_DOUBLE_EQ(coulombMagnitude(5.0, mu * N), 3.0);
  const Vector3d t(3.0, 0.0, -4.0);  // |t| = 5
  const Vector3d r = coulombReturnMap(t, mu * N);
  EXPECT_NEAR(r.norm(), mu * N, 1e-15 * mu * N);
  EXPECT_NEAR(r.normalized().dot(t.normalized()), 1.0, 1e-15);
  // mu = 0: frictionless, nothing is transmitted
  EXPECT_EQ(coulombScale(5.0, 0.0), 0.0);
}

// The engines' former form min(s, L) / s (MPM grid and surface contact):
// the same bits for every s > 0, so replacing it changed no result.
TEST(Coulomb, ScaleIsMinOverTrialToTheBit) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-6.0, 2.0);
  for (int i = 0; i < 10000; ++i) {
    const double s = std::pow(10.0, u(rng)), L = std::pow(10.0, u(rng));
    EXPECT_EQ(coulombScale(s, L), std::min(s, L) / s);
    EXPECT_EQ(coulombScale(s, s), std::min(s, s) / s);
  }
}

TEST(Coulomb, SlippingOnTheCone) {
  EXPECT_TRUE(coulombSlips(3.0, 3.0, 0.0));
  EXPECT_TRUE(coulombSlips(3.0 * (1 - 1e-12), 3.0, 1e-9));  // within the tolerance
  EXPECT_FALSE(coulombSlips(2.0, 3.0, 1e-9));
  EXPECT_FALSE(coulombSlips(0.0, 0.0, 1e-9));  // no force: not slipping
}

// The explicit solver's stick spring: a node sliding at v_t over a still
// surface takes -k dt v_t while it sticks, and -mu N v_t / |v_t| once it
// slips: opposite the sliding velocity, without a normal part.
TEST(Coulomb, StickSpringOpposesTheSlidingVelocity) {
  const Vector3d n(0, 0, 1), v(0.3, -0.4, 0.7);  // v_t = (0.3, -0.4, 0), |v_t| = 0.5
  const double kdt = 2.0, mu = 0.3;
  // stick: |k dt v_t| = 1 below mu N = 3
  const Vector3d s = stickSpringFriction(Vector3d::Zero(), n, v, kdt, mu * 10.0);
  EXPECT_NEAR((s - Vector3d(-0.6, 0.8, 0.0)).norm(), 0.0, 1e-15);
  // slip: the force of the last step plus the increment exceeds mu N = 0.6
  const Vector3d t = stickSpringFriction(Vector3d(0.0, 0.0, 5.0), n, v, kdt, mu * 2.0);
  EXPECT_NEAR(t.norm(), 0.6, 1e-15);
  EXPECT_NEAR(t.dot(Vector3d(0.3, -0.4, 0.0)) / (t.norm() * 0.5), -1.0, 1e-15);
  EXPECT_EQ(t.z(), 0.0);
  // the force of the last step is kept while sticking (its normal part dropped), a spring
  const Vector3d kept = stickSpringFriction(Vector3d(0.5, 0.0, 9.0), n, Vector3d::Zero(), kdt, 3.0);
  EXPECT_EQ(kept, Vector3d(0.5, 0.0, 0.0));
}

TEST(Coulomb, PairFrictionOpposesTheSlidingVelocity) {
  const double m[3] = {0.0, 0.0, 1.0}, vp[3] = {0.2, 0.1, -0.3}, vq[3] = {-0.1, 0.5, 0.4};
  // sliding velocity: (0.3, -0.4, -0.7) without its normal part: (0.3, -0.4, 0), |v_t| = 0.5
  const double mr = 2e-3, dt = 1e-4, mu = 0.3;
  // slip: m_r |v_t| / dt = 10 N above mu fN = 3 N
  double f[3] = {1.0, 2.0, 3.0};
  const double W = coulombPair(m, 10.0, vp, vq, mr, mu, dt, f);
  EXPECT_NEAR(f[0], 1.0 - 3.0 * 0.6, 1e-15);
  EXPECT_NEAR(f[1], 2.0 + 3.0 * 0.8, 1e-15);
  EXPECT_EQ(f[2], 3.0);
  EXPECT_NEAR(W, 3.0 * 0.5 * dt, 1e-18);  // work: friction force x slip
  // stick: mu fN = 30 N above 10 N: the force that stops the pair's sliding in the step
  double g[3] = {0.0, 0.0, 0.0};
  coulombPair(m, 100.0, vp, vq, mr, mu, dt, g);
  EXPECT_NEAR(g[0], -mr * 0.3 / dt, 1e-14);
  EXPECT_NEAR(g[1], mr * 0.4 / dt, 1e-14);
  // no sliding: no force, no work
  double h[3] = {0.0, 0.0, 0.0};
  const double vn[3] = {vq[0], vq[1], vq[2] + 1.0};  // relative velocity along the normal only
  EXPECT_EQ(coulombPair(m, 10.0, vn, vq, mr, mu, dt, h), 0.0);
  EXPECT_EQ(h[0], 0.0);
}

TEST(Coulomb, ScalarDerivativesMatchFiniteDifferences) {
  const double mu = 0.3;
  // (trial, N): slip (trial > mu N) and stick, each away from the kink
  for (const auto& [s, N] : {std::pair{5.0, 10.0}, std::pair{2.0, 10.0}, std::pair{0.7, 1.3}, std::pair{0.2, 1.3}}) {
    const CoulombSlope a = coulombScaleSlope(s, mu, N);
    const double fs = centralDifference([&](double x) { return coulombScale(x, mu * N); }, s, 1e-6 * s);
    const double fn = centralDifference([&](double x) { return coulombScale(s, mu * x); }, N, 1e-6 * N);
    EXPECT_NEAR(a.trial, fs, kFdTol * std::max(std::abs(fs), 1e-3)) << s << " " << N;
    EXPECT_NEAR(a.normal, fn, kFdTol * std::max(std::abs(fn), 1e-3)) << s << " " << N;
    const CoulombSlope b = coulombMagnitudeSlope(s, mu, N);
    const double gs = centralDifference([&](double x) { return coulombMagnitude(x, mu * N); }, s, 1e-6 * s);
    const double gn = centralDifference([&](double x) { return coulombMagnitude(s, mu * x); }, N, 1e-6 * N);
    EXPECT_NEAR(b.trial, gs, kFdTol) << s << " " << N;
    EXPECT_NEAR(b.normal, gn, kFdTol * mu) << s << " " << N;
  }
  // the branches themselves: slip d/dN = mu, stick d/dtrial = 1
  EXPECT_EQ(coulombMagnitudeSlope(5.0, mu, 10.0).normal, mu);
  EXPECT_EQ(coulombMagnitudeSlope(2.0, mu, 10.0).trial, 1.0);
}

TEST(Coulomb, ReturnMapJacobianMatchesFiniteDifferences) {
  const double mu = 0.3;
  for (const double N : {4.0, 40.0}) {  // slip (|t| = 3.74 > 1.2), stick (< 12)
    const Vector3d t(1.0, -2.0, 3.0);
    const Matrix3d J = coulombReturnMapJacobian(t, mu, N);
    const Matrix3d Jfd = jacobianFd([&](const Vector3d& x) { return coulombReturnMap(x, mu * N); }, t, 1e-6);
    EXPECT_LT((J - Jfd).norm(), kFdTol * J.norm()) << "N " << N;
    const Vector3d dN = coulombReturnMapNormalSlope(t, mu, N);
    const Vector3d dNfd =
        (coulombReturnMap(t, mu * (N + 1e-6 * N)) - coulombReturnMap(t, mu * (N - 1e-6 * N))) / (2e-6 * N);
    EXPECT_LT((dN - dNfd).norm(), kFdTol * std::max(dN.norm(), 1e-3)) << "N " << N;
  }
}

TEST(Coulomb, PairFrictionDerivativesMatchFiniteDifferences) {
  const Vector3d mn = Vector3d(0.2, -0.3, 0.9).normalized();
  const double m[3] = {mn[0], mn[1], mn[2]}, vq[3] = {0.0, 0.0, 0.0};
  const double mr = 2e-3, dt = 1e-4, mu = 0.3;
  const Vector3d w(0.3, -0.4, 0.1);
  const auto force = [&](const Vector3d& v, double fN) {
    const double vp[3] = {v[0], v[1], v[2]};
    double f[3] = {0.0, 0.0, 0.0};
    coulombPair(m, fN, vp, vq, mr, mu, dt, f);
    return Vector3d(f[0], f[1], f[2]);
  };
  for (const double fN : {10.0, 100.0}) {  // m_r |v_t| / dt ~ 10: slip at fN 10 (3 N), stick at 100 (30 N)
    const double vp[3] = {w[0], w[1], w[2]};
    Matrix3d dF;
    Vector3d dN;
    coulombPairSlope(m, fN, vp, vq, mr, mu, dt, dF, dN);
    const Matrix3d dFfd = jacobianFd([&](const Vector3d& v) { return force(v, fN); }, w, 1e-7);
    EXPECT_LT((dF - dFfd).norm(), kFdTol * dF.norm()) << "fN " << fN;
    const Vector3d dNfd = (force(w, fN * (1 + 1e-6)) - force(w, fN * (1 - 1e-6))) / (2e-6 * fN);
    EXPECT_LT((dN - dNfd).norm(), kFdTol * std::max(dN.norm(), 1e-3)) << "fN " << fN;
  }
}
