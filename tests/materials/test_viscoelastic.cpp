// Prony-series viscoelasticity (seed 001 eqs 1-4 as QLV).
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <cmath>

#include "needlesim/core/error.hpp"
#include "needlesim/materials/homogeneous.hpp"
#include "needlesim/materials/viscoelastic.hpp"

using namespace needlesim::materials;

namespace {
Prony twoTerms() {
  Prony p;
  p.terms = {{0.35, 0.8}, {0.25, 12.0}};
  return p;
}
}  // namespace

// A step strain at t = 0 relaxes as S0 G(t) (seed 001 eq 3). The update is exact
// for a stress constant within a step, so the error is round-off at any dt,
// from dt = tau_min / 1000 to dt = 40 tau_max.
TEST(Prony, StepRelaxationMatchesAnalyticAtSmallAndLargeSteps) {
  const Prony p = twoTerms();
  const double S0 = 1234.5;
  for (double dt : {0.8e-3, 0.05, 1.0, 30.0, 500.0}) {
    PronyState<double> st;
    double s = pronyUpdate(p, st, S0, 0.0);  // the jump
    EXPECT_NEAR(s, S0, 1e-12 * S0);
    double t = 0;
    int n = static_cast<int>(std::min(60.0 / dt, 20000.0)) + 1;
    for (int k = 0; k < n; ++k) {
      s = pronyUpdate(p, st, S0, dt);
      t += dt;
      ASSERT_NEAR(s, S0 * p.relaxation(t), 1e-10 * S0) << "dt " << dt << " t " << t;
    }
    EXPECT_GE(s, S0 * p.gInfinity() * (1 - 1e-12));  // never below the long-term value
  }
}

// A linear ramp then hold: the update is exact for piecewise linear S_e, so the
// numerical curve equals the closed form for coarse and fine ramp substeps.
TEST(Prony, RampRelaxationMatchesClosedForm) {
  const Prony p = twoTerms();
  const double peak = 800.0, tr = 2.0;
  std::vector<double> times;
  for (double t = 2.0; t < 100; t *= 1.3) times.push_back(t);
  for (int sub : {1, 7, 400}) {
    auto s = relaxationAfterRamp([&](double t) { return peak * t / tr; }, p, tr, times, sub);
    for (std::size_t i = 0; i < times.size(); ++i)
      EXPECT_NEAR(s[i], rampRelaxationClosedForm(p, peak, tr, times[i]), 1e-9 * peak) << sub;
  }
}

// Vector state (Voigt stress) and the algorithmic tangent factor dS/dS_e.
TEST(Prony, VectorStateAndTangentFactor) {
  const Prony p = twoTerms();
  using V6 = Eigen::Matrix<double, 6, 1>;
  PronyState<V6> st;
  V6 a = V6::Constant(1.0), b = V6::LinSpaced(1.0, 6.0);
  pronyUpdate(p, st, a, 0.1);
  PronyState<V6> st2 = st;
  const double dt = 0.37, eps = 1e-6;
  V6 s1 = pronyUpdate(p, st, b, dt);
  V6 s2 = pronyUpdate(p, st2, V6(b + eps * V6::Unit(2)), dt);
  EXPECT_NEAR((s2 - s1)[2] / eps, p.stepFactor(dt), 1e-6);
  EXPECT_NEAR(p.stepFactor(0.0), 1.0, 1e-12);
  EXPECT_NEAR(p.stepFactor(1e9), p.gInfinity(), 1e-6);
}

TEST(Prony, InvalidTermsAreRejected) {
  Prony p;
  p.terms = {{0.6, 1.0}, {0.5, 2.0}};
  EXPECT_THROW(p.validate(), needlesim::Error);
  p.terms = {{0.2, 0.0}};
  EXPECT_THROW(p.validate(), needlesim::Error);
  p.terms = {{-0.1, 1.0}};
  EXPECT_THROW(p.validate(), needlesim::Error);
  p.terms = {{0.2, 1.0}};
  EXPECT_NO_THROW(p.validate());
}
