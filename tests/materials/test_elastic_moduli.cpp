// The one small-strain conversion (elastic_moduli.hpp): closed forms and the
// round trip E, nu -> lambda, mu, K -> E, nu.
#include <gtest/gtest.h>

#include <cmath>

#include "needlesim/materials/elastic_moduli.hpp"
#include "needlesim/materials/homogeneous.hpp"
#include "needlesim/materials/hyperelastic.hpp"

using namespace needlesim::materials;

// E = 2.6, nu = 0.3: mu = 2.6 / 2.6 = 1, lambda = 0.78 / 0.52 = 1.5, K = 2.6 / 1.2 = 1.5 + 2/3.
TEST(ElasticModuli, ClosedForms) {
  const Lame l = lame(2.6, 0.3);
  EXPECT_DOUBLE_EQ(l.mu, 1.0);
  EXPECT_DOUBLE_EQ(l.lambda, 1.5);
  EXPECT_DOUBLE_EQ(bulkModulus(2.6, 0.3), 1.5 + 2.0 / 3.0);
  EXPECT_DOUBLE_EQ(bulkFromShear(1.0, 0.3), bulkModulus(2.6, 0.3));
  // nu = 0: no lateral coupling, lambda = 0, mu = E / 2
  EXPECT_EQ(lame(3.0, 0.0).lambda, 0.0);
  EXPECT_EQ(lame(3.0, 0.0).mu, 1.5);
}

TEST(ElasticModuli, RoundTrip) {
  for (const double nu : {-0.5, 0.0, 0.25, 0.422, 0.499})
    for (const double E : {1e3, 30.74e3, 2e9}) {
      const Lame l = lame(E, nu);
      const double K = bulkModulus(E, nu);
      EXPECT_NEAR(l.lambda + 2.0 / 3.0 * l.mu, K, 1e-12 * K) << E << " " << nu;
      EXPECT_NEAR(bulkFromShear(l.mu, nu), K, 1e-12 * K);
      const YoungPoisson back = youngPoisson(K, l.mu);
      EXPECT_NEAR(back.E, E, 1e-12 * E) << E << " " << nu;
      EXPECT_NEAR(back.nu, nu, 1e-12) << E << " " << nu;
    }
}

// A law's small-strain constants: lame(E, nu) for linear, (K - 2/3 mu0, mu0) otherwise.
TEST(ElasticModuli, InitialModuliOfALaw) {
  Hyperelastic lin;
  lin.kind = LawKind::Linear;
  lin.E = 30.74e3;
  lin.nu = 0.422;
  EXPECT_EQ(lin.initialLame().lambda, lame(lin.E, lin.nu).lambda);
  EXPECT_EQ(lin.initialShear(), lame(lin.E, lin.nu).mu);
  EXPECT_EQ(lin.initialBulk(), bulkModulus(lin.E, lin.nu));
  Hyperelastic nh;
  nh.kind = LawKind::NeoHookean;
  nh.C10 = 3.6e3;
  nh.bulk = 1e5;
  EXPECT_DOUBLE_EQ(nh.initialLame().mu, 7.2e3);
  EXPECT_DOUBLE_EQ(nh.initialLame().lambda, 1e5 - 4.8e3);
  EXPECT_EQ(nh.initialBulk(), 1e5);
}

// The nominal stress of a spec (the pain index's basic stress): the law's
// exact incompressible response, E (lambda - 1) for linear.
TEST(ElasticModuli, UniaxialNominalOfASpec) {
  MaterialSpec lin;
  lin.law = "linear";
  lin.params = {{"E", 30e3}, {"nu", 0.45}};
  EXPECT_DOUBLE_EQ(uniaxialNominalIncompressible(lin, 0.7), -9e3);
  MaterialSpec nh;
  nh.law = "neo-hookean";
  nh.params = {{"C10", 5e3}, {"nu", 0.495}};
  EXPECT_EQ(uniaxialNominalIncompressible(nh, 0.7), uniaxialNominalIncompressible(Hyperelastic::fromSpec(nh), 0.7));
  EXPECT_NEAR(uniaxialNominalIncompressible(nh, 0.7), 2 * 5e3 * (0.7 - 1 / 0.49), 1e-9 * 5e3);
}
