// The needle's cut (needle_cut.cpp) leaves out the support nodes across it and renormalises a
// point's weights over the nodes it still reaches. That keeps a partition of unity, so a rigid
// translation of the tissue with the needle stays a rigid translation: every point keeps its
// velocity, F stays the identity and the total momentum stays M v0 (seed 000 eqs 2-4 with
// weights summing to one). Weights that did not sum to one would change the gathered velocities.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "needlesim/engines/mpm/mpm_solver.hpp"
#include "needlesim/materials/hyperelastic.hpp"

using namespace needlesim::mpm;

namespace {

MpmSolver translatingBlockWithACuttingNeedle(const Vec3& v0, int threads) {
  const double h = 0.8e-3, dp = 0.4e-3;
  MpmConfig cfg;
  cfg.h = h;
  cfg.threads = threads;
  cfg.origin = Vec3(-4 * h, -6e-3, -6e-3);
  cfg.cells = {20, 15, 15};
  cfg.boxLo = Vec3(0, -3e-3, -3e-3);
  cfg.boxHi = Vec3(8e-3, 3e-3, 3e-3);
  cfg.massScaling = 1e4;
  MpmSolver s(cfg);
  MpmMaterial m;
  m.law.kind = needlesim::materials::LawKind::Fung;
  m.law.mu = 5e3;
  m.law.gamma = 2.0;
  m.law.bulk = 2.5e5;
  m.density = 1000;
  s.addMaterial(m);
  s.addBlock(cfg.boxLo, cfg.boxHi, dp, 0, 0, v0);
  RigidBody n;
  n.kind = RigidBody::Kind::Needle;
  n.tip = RigidBody::Tip::Bevel;
  n.radius = 0.44e-3;
  n.tipAngle = 20 * std::numbers::pi / 180;
  n.bevelSide = -Vec3::UnitY();
  n.point = Vec3(4e-3, 0.44e-3, 0.1e-3);  // the tip 4 mm inside: the cut crosses the block
  n.velocity = v0;                        // moving with the tissue: no relative motion, no contact
  n.friction = 0.255;
  n.parting = true;
  s.addRigid(n);
  s.finalize();
  return s;
}

}  // namespace

TEST(MpmCut, ARigidTranslationStaysRigidAcrossTheCut) {
  const Vec3 v0(1e-3, 2e-3, -0.5e-3);
  for (int threads : {1, 2}) {
    MpmSolver s = translatingBlockWithACuttingNeedle(v0, threads);
    double mass = 0.0;
    for (std::size_t p = 0; p < s.size(); ++p) mass += s.mass(p);
    std::size_t cut = 0;
    for (int i = 0; i < 20; ++i) {
      s.step();
      cut = std::max(cut, s.cutPoints());
      s.rigid(0).point += v0 * s.lastReport().dt;
    }
    ASSERT_GT(cut, 0u) << "the cut must cross the block for the test to mean anything";
    Vec3 momentum = Vec3::Zero();
    double worstV = 0.0, worstF = 0.0;
    for (std::size_t p = 0; p < s.size(); ++p) {
      momentum += s.mass(p) * s.velocity(p);
      worstV = std::max(worstV, (s.velocity(p) - v0).norm() / v0.norm());
      worstF = std::max(worstF, (s.defGrad(p) - Mat3::Identity()).norm());
    }
    EXPECT_LT(worstV, 1e-10) << threads << " thread(s): a point's velocity left the translation";
    EXPECT_LT(worstF, 1e-10) << threads << " thread(s): a point deformed under a rigid translation";
    EXPECT_LT((momentum - mass * v0).norm(), 1e-10 * mass * v0.norm()) << threads << " thread(s)";
    EXPECT_FALSE(s.rigidForce(0).total.norm() > 1e-12) << "a needle moving with the tissue is loaded";
  }
}
