// Contact pressure and area output (contact_output.hpp) and the end-of-step normal contact
// (contact_normal.cpp): a block pressed onto a frictionless rigid plane by a uniform pressure q
// on its top face (consistent nodal loads) comes to rest in a homogeneous stress state
// (sigma_yy = -q, which one-point elements represent exactly: patch test), so the contact
// area is the base area, the mean pressure is q (momentum balance) and every nodal pressure is
// q (lumped tributary areas are exact for a uniform traction on linear facets).
#include <gtest/gtest.h>

#include <cmath>

#include "needlesim/engines/explicit/contact_output.hpp"
#include "needlesim/engines/explicit/solver.hpp"

using namespace needlesim;
using namespace needlesim::explicit_fe;

namespace {
Material rubber() {
  materials::MaterialSpec sp;
  sp.law = "neo-hookean";
  sp.params = {{"C10", 5e4}, {"K", 5e5}};
  sp.density = 1000.0;
  return Material::fromSpec(sp);
}

void restOnPlane(const Mesh& m, const std::vector<double>& xs, const std::vector<double>& zs, double q,
                 double* area, double* pMean, double* pMin, double* pMax, double* pen) {
  SolverOptions o;
  o.damping = 2000.0;  // dynamic relaxation: ~ 2 x the block's lowest frequency
  ExplicitSolver s(m, {rubber()}, o);
  RigidPlane pl;
  pl.normal = Eigen::Vector3d::UnitY();
  s.addPlane(pl);
  const int d = m.dim;
  double ytop = 0;
  for (int n = 0; n < m.nodes(); ++n) ytop = std::max(ytop, m.coord(n, 1));
  auto trib = [](const std::vector<double>& c, double v) {
    double t = 0;
    for (std::size_t i = 0; i < c.size(); ++i)
      if (std::abs(c[i] - v) < 1e-12) t = (i > 0 ? 0.5 * (c[i] - c[i - 1]) : 0.0) + (i + 1 < c.size() ? 0.5 * (c[i + 1] - c[i]) : 0.0);
    return t;
  };
  for (int n = 0; n < m.nodes(); ++n)
    if (std::abs(m.coord(n, 1) - ytop) < 1e-12)
      s.setExternalForce(n, 1, -q * trib(xs, m.coord(n, 0)) * (d == 3 ? trib(zs, m.coord(n, 2)) : 1.0));
  s.advanceTo(0.05);
  ContactOutput co(m);
  co.update(s);
  *area = co.contactArea();
  *pMean = co.meanPressure();
  *pMin = 1e300, *pMax = 0, *pen = 0;
  for (int n = 0; n < m.nodes(); ++n)
    if (std::abs(m.coord(n, 1)) < 1e-12) {
      *pMin = std::min(*pMin, co.pressure()[n]);
      *pMax = std::max(*pMax, co.pressure()[n]);
      *pen = std::max(*pen, -s.displacement()[static_cast<std::size_t>(n) * d + 1]);
    }
}
}  // namespace

TEST(ExplicitContactOutput, BlockOnPlanePressureAndArea2D) {
  // 40 x 20 mm block, graded columns (unequal tributary lengths)
  const std::vector<double> xs = {0, 0.004, 0.01, 0.018, 0.028, 0.04};
  Mesh m = structuredBlock(xs, {0, 0.005, 0.01, 0.02}, ElementType::Quad4);
  const double q = 2000.0;
  double A, pm, pmin, pmax, pen;
  restOnPlane(m, xs, {}, q, &A, &pm, &pmin, &pmax, &pen);
  std::printf("2D: area %.6g (base 0.04), mean pressure %.6g (q %.6g), nodal %.6g .. %.6g, penetration %.3g m\n",
              A, pm, q, pmin, pmax, pen);
  // the base widens by the lateral strain nu' q / E' ~ 3e-3 (plane strain, E = 3e5 Pa): the area follows
  EXPECT_GT(A, 0.04);
  EXPECT_LT(A, 0.04 * (1 + 0.01));
  EXPECT_NEAR(pm * A, q * 0.04, 1e-3 * q * 0.04);  // the load reaches the plane (damped to rest)
  EXPECT_LT(pmax / pmin - 1, 1e-3);                // uniform
  EXPECT_LT(pen, 1e-3 * 0.004);                    // default penalty: penetration << element size
}

TEST(ExplicitContactOutput, BlockOnPlanePressureAndArea3D) {
  const std::vector<double> xs = {0, 0.01, 0.016, 0.03}, zs = {0, 0.008, 0.02, 0.03};
  Mesh m = structuredBlock(xs, {0, 0.01, 0.02}, zs, ElementType::Hex8);
  const double q = 2000.0;
  double A, pm, pmin, pmax, pen;
  restOnPlane(m, xs, zs, q, &A, &pm, &pmin, &pmax, &pen);
  std::printf("3D: area %.6g (base 9e-4), mean pressure %.6g (q %.6g), nodal %.6g .. %.6g, penetration %.3g m\n",
              A, pm, q, pmin, pmax, pen);
  EXPECT_GT(A, 9e-4);
  EXPECT_LT(A, 9e-4 * (1 + 0.02));
  EXPECT_NEAR(pm * A, q * 9e-4, 1e-3 * q * 9e-4);
  EXPECT_LT(pmax / pmin - 1, 1e-3);
  EXPECT_LT(pen, 1e-3 * 0.006);
}
