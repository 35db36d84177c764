// Euler-Bernoulli Hermite beam element and straight-beam solver against closed forms.
#include <gtest/gtest.h>

#include <cmath>

#include "needlesim/needle/beam_element.hpp"
#include "needlesim/needle/beam_solver.hpp"

using namespace needlesim::needle;

TEST(Beam, CantileverTipLoadIsExact) {
  // w(L) = P L^3 / (3 EI), theta(L) = P L^2 / (2 EI): cubic Hermite elements are exact.
  const double EI = 1.1e-4, L = 0.15, P = 2e-3;
  for (int ne : {1, 3, 10}) {
    StraightBeam b{EI, L, ne, {}};
    const BeamSolution s = solveStraightBeam(b, {{ne, P, 0.0}});
    EXPECT_NEAR(s.w.back(), P * L * L * L / (3 * EI), 1e-12 * P * L * L * L / EI) << ne;
    EXPECT_NEAR(s.theta.back(), P * L * L / (2 * EI), 1e-12 * P * L * L / EI) << ne;
  }
}

TEST(Beam, CantileverTipMomentAndUniformLoad) {
  const double EI = 2.0, L = 1.0, M = 0.3, q = 0.7;
  StraightBeam b{EI, L, 4, {}};
  const BeamSolution s = solveStraightBeam(b, {{4, 0.0, M}});
  EXPECT_NEAR(s.w.back(), M * L * L / (2 * EI), 1e-13);
  // uniform load q via consistent load vectors: w(L) = q L^4 / (8 EI), exact at nodes
  std::vector<NodalLoad> loads;
  const int ne = 8;
  const double h = L / ne;
  for (int e = 0; e < ne; ++e) {
    const Vec4 f = uniformLoad(q, h);
    loads.push_back({e, f(0), f(1)});
    loads.push_back({e + 1, f(2), f(3)});
  }
  StraightBeam b8{EI, L, ne, {}};
  const BeamSolution u = solveStraightBeam(b8, loads);
  EXPECT_NEAR(u.w.back(), q * L * L * L * L / (8 * EI), 1e-12);
}

// The closed-form cantilever influence functions (the realtime2d needle's condensed
// coupling, seed 003 eq 3.12) against the assembled Hermite FE (eq 3.14) for arbitrary
// point loads at the nodes: the FE is exact for point loads, so they agree to round-off.
TEST(Beam, CantileverInfluenceFunctionsMatchTheFE) {
  const double EI = 0.0206, L = 0.1, P = 0.12;
  StraightBeam b{EI, L, 10, {}};
  const BeamSolution tip = solveStraightBeam(b, {{10, P, 0.0}});
  EXPECT_NEAR(tip.w.back(), P * cantileverDeflection(L, L, EI), 1e-14);
  EXPECT_NEAR(tip.theta.back(), P * cantileverSlope(L, L, EI), 1e-13);
  const double F[11] = {0, 0.1, -0.3, 0, 0.2, 0.05, 0, 0, -0.1, 0.4, 0.12};
  std::vector<NodalLoad> loads;
  for (int j = 1; j <= 10; ++j) loads.push_back({j, F[j], 0.0});
  const BeamSolution s = solveStraightBeam(b, loads);
  for (int i = 1; i <= 10; ++i) {
    double wc = 0, tc = 0;
    for (int j = 1; j <= 10; ++j) {
      wc += F[j] * cantileverDeflection(s.x[i], s.x[j], EI);
      tc += F[j] * cantileverSlope(s.x[i], s.x[j], EI);
    }
    EXPECT_NEAR(s.w[i], wc, 1e-12) << i;
    EXPECT_NEAR(s.theta[i], tc, 1e-12) << i;
  }
}

TEST(Beam, HetenyiSemiInfiniteBeamOnWinklerFoundation) {
  // Free end of a long beam on a Winkler foundation k under end force P and moment M0
  // (Hetenyi 1946): w(0) = 2 lambda (P - lambda M0) / k, theta(0) = -2 lambda^2 (P - 2 lambda M0) / k
  // with x into the beam and lambda = (k / 4 EI)^(1/4). Here the free end is at x = L and
  // the beam is clamped far away (L lambda = 20): slope sign flips with the x direction.
  const double EI = 1.1e-4, k = 9.21e3;
  const double lambda = std::pow(k / (4 * EI), 0.25);
  const double L = 20 / lambda, P = 1e-3, M0 = 2e-6;
  double prev_err = 1e9;
  for (int ne : {25, 50, 100, 200, 400}) {
    StraightBeam b{EI, L, ne, std::vector<double>(ne, k)};
    const BeamSolution s = solveStraightBeam(b, {{ne, P, -M0}});
    const double w0 = 2 * lambda * (P - lambda * M0) / k;
    const double t0 = 2 * lambda * lambda * (P - 2 * lambda * M0) / k;
    const double err = std::abs(s.w.back() - w0) / std::abs(w0);
    EXPECT_NEAR(s.theta.back(), t0, 2e-2 * std::abs(t0) * 25.0 / ne + 1e-6 * std::abs(t0)) << ne;
    // mesh convergence: the error must fall with refinement (O(h^4) for Hermite elements)
    EXPECT_LT(err, prev_err) << ne;
    prev_err = err;
    if (ne >= 100) {
      EXPECT_LT(err, 1e-4) << ne;
    }
    // decay: deflection at x = pi / lambda from the free end follows e^-pi (-cos...)
  }
}

TEST(Beam, GeometricStiffnessGivesEulerBuckling) {
  // Cantilever under compression: the tangent stiffness turns singular at P = pi^2 EI / (4 L^2).
  const double EI = 1.0, L = 1.0, Pcr = std::acos(-1.0) * std::acos(-1.0) / 4;
  StraightBeam b{EI, L, 20, {}};
  b.axial_force = -0.98 * Pcr;
  EXPECT_NO_THROW(solveStraightBeam(b, {{20, 1e-3, 0}}));
  b.axial_force = -1.02 * Pcr;
  EXPECT_THROW(solveStraightBeam(b, {{20, 1e-3, 0}}), std::runtime_error);
}

TEST(Beam, FrameElementRigidBodyModesAndRotation) {
  // A rotated frame element must have three zero-energy modes (two translations, one rotation).
  const Mat6 K = frameStiffnessGlobal(1e3, 2.0, 0.1, 0.2, 0.4, 0.6);
  Vec6 tx, ty, rz;
  tx << 1, 0, 0, 1, 0, 0;
  ty << 0, 1, 0, 0, 1, 0;
  rz << -0.2, 0.1, 1, -0.6, 0.4, 1;  // rotation about the origin
  EXPECT_LT((K * tx).norm(), 1e-9);
  EXPECT_LT((K * ty).norm(), 1e-9);
  EXPECT_LT((K * rz).norm(), 1e-9);
  // axial stretch costs EA/h
  Vec6 ax;
  ax << 0, 0, 0, 0.6, 0.8, 0;
  EXPECT_NEAR(ax.dot(K * ax), 1e3 / 0.5, 1e-9);
}
