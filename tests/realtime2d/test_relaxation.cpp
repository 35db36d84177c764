// Beyond the thesis: tissue relaxation through Prony viscoelasticity (QLV on the whole
// stiffness, materials/viscoelastic.hpp, seed 001 eqs 1-4) and the stiffening around the
// needle (seed 003 section 3.5 item 4).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>

#include "needlesim/engines/realtime2d/session.hpp"

using namespace needlesim::realtime2d;

namespace {
SessionConfig insertionConfig(int nx = 17, int ny = 13) { return thesisGelatinConfig(nx, ny); }
}  // namespace

// A step load on a path node of a QLV tissue (G = g_inf + g exp(-t/tau)) creeps as the
// standard linear solid: u(t) = u_e [1/g_inf - (1/g_inf - 1) exp(-g_inf t/tau)], with u_e
// the elastic static response. Checked for the three back-ends.
TEST(Realtime2dRelaxation, PronyCreepMatchesStandardLinearSolid) {
  const double g = 0.5, tau = 0.5, ginf = 1.0 - g;
  for (Backend b : {Backend::Modal, Backend::Direct, Backend::Reduced}) {
    TissueConfig tc;
    tc.mesh.nodes_depth = 13;
    tc.mesh.nodes_lateral = 17;
    tc.rayleigh_alpha = 50.0;  // damp the inertial transient (quasi-static creep)
    tc.rayleigh_beta = 1e-3;
    tc.prony = {{g, tau}};
    tc.backend = b;
    tc.reduced_max_modes = 20;  // most modes residual
    const double dt = 1e-3;
    Tissue t(tc, Eigen::Vector2d(0.0, 0.06), Eigen::Vector2d(1.0, 0.0), dt);
    ASSERT_EQ(t.backend(), b);
    const int k = 2 * 4 + 1;  // lateral load on path node 4
    Eigen::VectorXd f = Eigen::VectorXd::Zero(t.pathDofs());
    f[k] = 0.01;  // N
    Eigen::VectorXd full = Eigen::VectorXd::Zero(2 * t.mesh().nodeCount());
    full[2 * t.path()[4].node + 1] = 0.01;
    const double ue = t.staticSolve(full)[2 * t.path()[4].node + 1];
    ASSERT_GT(ue, 0.0);
    for (int n = 1; n <= 2000; ++n) {
      t.predict();
      t.commit(f);
      const double time = n * dt;
      if (n == 500 || n == 1000 || n == 2000) {
        const double J = 1.0 / ginf - (1.0 / ginf - 1.0) * std::exp(-ginf * time / tau);
        EXPECT_NEAR(t.pathU()[k], ue * J, 0.02 * ue * J) << "backend " << static_cast<int>(b) << " t " << time;
      }
    }
    // Without relaxation the long-time response is the elastic one (the factor 2 is Prony's).
    EXPECT_GT(t.pathU()[k], 1.8 * ue);
  }
}

// In a relaxing (QLV) tissue the shaft friction, a force-controlled load while the shaft slips
// (C + b v_rel, seed 003 eq 3.23), drags the tissue further as it creeps: over an insertion
// much longer than tau the dragged displacement approaches 1/g_inf times the elastic one.
// In a pause afterwards the held friction and the displacement it causes keep relaxing.
TEST(Realtime2dRelaxation, ShaftFrictionCreepsTheRelaxingTissue) {
  double ux[2], uxPause[2];
  const double g = 0.4, tau = 1.0;
  for (int k = 0; k < 2; ++k) {
    auto c = insertionConfig();
    if (k == 1) c.tissue.prony = {{g, tau}};
    Session s(c);
    for (int n = 1; n <= 10000; ++n) s.step(s.poseAtDepth(3e-3 * n * c.dt), c.dt);  // 30 mm in 10 s
    ux[k] = s.tissue().pathU()[2];  // first path node below the entry face, axial
    for (int n = 0; n < 4000; ++n) s.step(s.poseAtDepth(0.03), c.dt);  // 4 s pause
    uxPause[k] = s.tissue().pathU()[2];
  }
  std::printf("dragged node: elastic %.3f mm, QLV %.3f mm (ratio %.3f, 1/g_inf = %.3f); after the pause %.3f, %.3f mm\n",
              ux[0] * 1e3, ux[1] * 1e3, ux[1] / ux[0], 1.0 / (1.0 - g), uxPause[0] * 1e3, uxPause[1] * 1e3);
  EXPECT_GT(ux[0], 0.0);
  EXPECT_GT(ux[1] / ux[0], 1.3);
  EXPECT_LT(ux[1] / ux[0], 1.0 / (1.0 - g) + 0.02);
}

// Stiffening around the needle (seed 003 section 3.5 item 4): the zone is 4x stiffer, so the
// shaft drags the tissue next to it less while the friction (slip) force stays the same.
TEST(Realtime2dRelaxation, StiffeningAroundTheNeedleReducesDrag) {
  double ux[2], F[2];
  for (int k = 0; k < 2; ++k) {
    auto c = insertionConfig(21, 31);
    if (k == 1) {
      c.tissue.stiffening_factor = 4.0;
      c.tissue.stiffening_radius = 6e-3;
    }
    Session s(c);
    for (int n = 1; n <= 10000; ++n) s.step(s.poseAtDepth(3e-3 * n * c.dt), c.dt);  // 30 mm
    ux[k] = s.tissue().pathU()[2 * 2];  // path node at 8 mm depth, axial
    F[k] = s.last().friction_force;
  }
  EXPECT_GT(ux[0], 0.0);
  EXPECT_LT(ux[1], 0.75 * ux[0]);  // measured 0.61: the tissue beyond the zone still gives
  EXPECT_NEAR(F[1], F[0], 0.05 * F[0]);
}
