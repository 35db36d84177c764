// The real-time engines' force bookkeeping (engines/realtime): the tip's cutting load is counted
// once (seed 003 eq 3.24), the shaft's contact lengths add up to the shaft in the tissue when path
// nodes overtake one another (eq 3.23 per length), the static limits D_p, D_n are used as given,
// and the linear-range check of the tissue's strains (realtime/linear_range.hpp).
#include <gtest/gtest.h>

#include <cmath>

#include "needlesim/engines/memory_sink.hpp"
#include "needlesim/engines/realtime/linear_range.hpp"
#include "needlesim/engines/realtime/shaft_coupling.hpp"
#include "needlesim/engines/realtime2d/session.hpp"

using namespace needlesim;
using namespace needlesim::realtime2d;

namespace {
SessionConfig frictionless() {
  SessionConfig c = thesisGelatinConfig(21, 13);
  c.puncture_force = 0.05;
  c.friction.C_p = c.friction.C_n = c.friction.b_p = c.friction.b_n = c.friction.D_p = c.friction.D_n = 0.0;
  return c;
}
}  // namespace

// Without friction the tissue resists only the cutting at the tip: the axial force is the
// cutting force at every depth (no share of it counted again on the path nodes).
TEST(Realtime2dBookkeeping, WithoutFrictionTheAxialForceIsTheCuttingForceAtEveryDepth) {
  const SessionConfig c = frictionless();
  Session s(c);
  int cutting = 0, off = 0;
  double worst = 0.0;
  for (int n = 1; n <= 20000; ++n) {  // 60 mm at 3 mm/s, across 15 node spacings
    const auto& r = s.step(s.poseAtDepth(-1e-3 + 3e-3 * n * c.dt), c.dt);
    if (r.phase != Phase::Cutting) continue;
    ++cutting;
    EXPECT_EQ(r.cutting_force, c.cutting_force);
    const double e = std::max(std::abs(r.axial_force - c.cutting_force), std::abs(r.friction_force));
    worst = std::max(worst, e);
    off += e > 1e-12;
  }
  EXPECT_GT(cutting, 15000);
  EXPECT_EQ(off, 0) << "largest difference " << worst << " N";
}

// Node 0 dragged past nodes 1-3: the lengths follow the current order along the axis (halfway
// boundaries, from the entry at 0 to the tip at 5 mm), none is negative, and they add up to 5 mm.
TEST(RealtimeShaftCoupling, ContactLengthsAddUpWhenNodesOvertake) {
  realtime::ShaftSettings st;
  st.engine = "test";
  st.lateral = 1;
  st.EI = 1.0;
  st.length = 0.1;
  st.path_s = {0.0, 1e-3, 2e-3, 3e-3, 4e-3, 6e-3};
  st.friction.assign(st.path_s.size(), FrictionSpec{});
  realtime::ShaftCoupling sh(st);
  Eigen::VectorXd pu = Eigen::VectorXd::Zero(2 * 6);
  pu[0] = 3.5e-3;  // node 0 at 3.5 mm
  sh.couple(true, 5e-3, pu);
  ASSERT_EQ(sh.coupled(), 5);
  sh.measure(5e-3, 1.0, pu);
  // order 1, 2, 3, 0, 4 at 1, 2, 3, 3.5, 4 mm: [0, 1.5], [1.5, 2.5], [2.5, 3.25], [3.25, 3.75], [3.75, 5]
  const double expected[] = {0.5e-3, 1.5e-3, 1e-3, 0.75e-3, 1.25e-3};
  double sum = 0.0;
  for (int i = 0; i < 5; ++i) {
    EXPECT_NEAR(sh.contactLength(i), expected[i], 1e-15) << i;
    sum += sh.contactLength(i);
  }
  EXPECT_NEAR(sum, 5e-3, 1e-15);
}

// The static limits are used as given (contact/karnopp.hpp): D = 0 is no static friction, so a
// sticking node holds no load and goes to the limit at once; it is not replaced by C.
TEST(RealtimeShaftCoupling, StaticLimitsAreUsedAsGiven) {
  realtime::ShaftSettings st;
  st.path_s = {0.0, 1e-3};
  FrictionSpec f;
  f.C_p = f.C_n = 3.791;
  f.static_band = 1e-4;
  st.friction.assign(2, f);
  const realtime::ShaftCoupling sh(st);
  EXPECT_EQ(sh.settings().friction[0].D_p, 0.0);
  EXPECT_EQ(sh.settings().friction[1].D_n, 0.0);
  using S = contact::KarnoppState;
  EXPECT_EQ(contact::karnoppNext(S::Stick, f, 1e-6, 0.0), S::HoldPos);
  EXPECT_EQ(contact::karnoppNext(S::Stick, f, -1e-6, 0.0), S::HoldNeg);
  f.D_p = f.D_n = 4.0;
  EXPECT_EQ(contact::karnoppNext(S::Stick, f, 3.9, 0.0), S::Stick);
  EXPECT_EQ(contact::karnoppNext(S::Stick, f, 4.1, 0.0), S::HoldPos);
  // hold -> slide at half the band, as karnoppPerLength leaves its static branch
  EXPECT_EQ(contact::karnoppNext(S::HoldPos, f, 4.1, 0.49e-4), S::HoldPos);
  EXPECT_EQ(contact::karnoppNext(S::HoldPos, f, 4.1, 0.5e-4), S::SlipPos);
  EXPECT_EQ(contact::karnoppPerLength(f, 0.5e-4, 0.0), contact::karnoppSliding(f, true, 0.5e-4));
  EXPECT_EQ(contact::karnoppNext(S::SlipNeg, f, 0.0, -0.4e-4), S::Stick);
}

// A uniform stretch of 10 % along x: the strain of every corner triangle of a square is 0.1;
// pushing one corner through the opposite edge inverts the triangles at it.
TEST(RealtimeLinearRange, StrainsAndInvertedElementsOfQuads) {
  const std::vector<double> X{0, 0, 1, 0, 1, 1, 0, 1};
  const realtime::SimplexStrains s(2, X, realtime::quadCornerTriangles({{0, 1, 2, 3}}));
  Eigen::VectorXd u(8);
  u << 0, 0, 0.1, 0, 0.1, 0, 0, 0;
  auto d = s.measure(u);
  EXPECT_NEAR(d.max_strain, 0.1, 1e-12);
  EXPECT_EQ(d.inverted, 0);
  u.setZero();
  u[4] = -1.5, u[5] = -1.5;  // corner 2 to (-0.5, -0.5)
  d = s.measure(u);
  EXPECT_GE(d.inverted, 1);
  MemorySink sink;
  realtime::LinearRangeWarning w("realtime2d");
  EXPECT_FALSE(w.check({0.1, 0}, 1e-3, sink));
  EXPECT_TRUE(sink.warnings.empty());
  EXPECT_TRUE(w.check(d, 2e-3, sink));
  EXPECT_TRUE(w.check({0.5, 0}, 3e-3, sink));
  ASSERT_EQ(sink.warnings.size(), 1u);  // once
  EXPECT_NE(sink.warnings[0].find("inverted"), std::string::npos);
  EXPECT_NE(sink.warnings[0].find("2 mm"), std::string::npos);
}
