// Hyperelastic + Prony wrapper used by the engines.
#include <gtest/gtest.h>

#include "needlesim/materials/homogeneous.hpp"
#include "needlesim/materials/tissue_law.hpp"
#include "needlesim/core/error.hpp"

using namespace needlesim::materials;

namespace {
TissueLaw gelWithProny() {
  MaterialSpec s;
  s.law = "neo-hookean";
  s.params = {{"C10", 3.6e3}, {"nu", 0.45}};
  s.prony = {{0.3, 0.5}, {0.2, 5.0}};
  return TissueLaw::fromSpec(s);
}
}  // namespace

// A held deformation relaxes every stress component as G(t) (exact at any dt),
// and a trial evaluation leaves the committed state untouched.
TEST(TissueLaw, HeldDeformationRelaxesAsG) {
  TissueLaw law = gelWithProny();
  Mat3 F;
  F << 1.1, 0.05, 0, 0.02, 0.95, 0.03, 0, 0.01, 0.97;
  Mat3 Se = evaluate(law.elastic, F, false).S;
  PointState3 st, next;
  evaluate(law, st, F, 0.0, next);  // the jump
  st = next;
  double t = 0;
  for (double dt : {0.01, 0.3, 2.0, 50.0}) {
    PointState3 trial;
    evaluate(law, st, F, dt, trial);  // trial, not committed
    auto s = evaluate(law, st, F, dt, next);
    t += dt;
    st = next;
    EXPECT_LT((s.S - law.prony.relaxation(t) * Se).norm(), 1e-10 * Se.norm()) << t;
  }
  // plane strain: S33 relaxes too
  Mat2 F2;
  F2 << 1.1, 0.05, 0.02, 0.92;
  Stress2 e = evaluatePlaneStrain(law.elastic, F2, false);
  PointState2 s2, n2;
  evaluatePlaneStrain(law, s2, F2, 0.0, n2);
  auto r = evaluatePlaneStrain(law, n2, F2, 1.0, s2);
  EXPECT_NEAR(r.sigma33, law.prony.relaxation(1.0) * e.sigma33, 1e-10 * std::abs(e.sigma33));
  EXPECT_LT((r.tangent - law.prony.stepFactor(1.0) * evaluatePlaneStrain(law.elastic, F2).tangent).norm(), 1e-9 * r.tangent.norm());
}

TEST(TissueLaw, InvalidPronyInSpecIsRejected) {
  MaterialSpec s;
  s.law = "fung";
  s.params = {{"mu", 1e3}, {"gamma", 2.0}};
  s.prony = {{0.7, 1.0}, {0.4, 2.0}};
  EXPECT_THROW(TissueLaw::fromSpec(s), needlesim::Error);
}
