// realtime3d against the explicit engine's solver (engines/explicit/solver.hpp) on a small 3D case:
// the same tetrahedral block, supports and path loads; explicit central differences with mass-
// proportional damping (dynamic relaxation) to rest against realtime3d's static solution.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "needlesim/engines/explicit/solver.hpp"
#include "needlesim/engines/realtime3d/session.hpp"
#include "../support/explicit_relaxation.hpp"
#include "../support/tet_nodes.hpp"

using namespace needlesim;

// Both use constant-strain tets on one mesh, so they must agree up to what differs in the
// models: the explicit solver's finite-strain kinematics (St Venant-Kirchhoff; strains here are
// below 1e-3, a relative effect of that order) and the residual motion of the dynamic relaxation
// (0.3 s at a damping of 300/s). 0.5% of the largest displacement covers both (0.05% measured).
using needlesim::testing::nearestNode;

TEST(Realtime3dExplicit, StaticPathLoadAgreesWithExplicitDynamicRelaxation) {
  auto c = realtime3d::gelatinBlockConfig(9, 7, realtime3d::Backend::Direct);
  c.tissue.block.length = c.tissue.block.width = c.tissue.block.height = 0.04;
  c.tissue.block.grading = 2.0;
  realtime3d::Session rt(c);
  const auto& mesh = rt.mesh();
  const int node = nearestNode(mesh, rt.tissue().path()[15].X);  // the path node 15 mm deep
  const Eigen::Vector3d load(2e-3, 3e-3, -1e-3);  // N on one path node
  Eigen::VectorXd F = Eigen::VectorXd::Zero(3 * mesh.nodes());
  F.segment<3>(3 * node) = load;
  const Eigen::VectorXd u = rt.tissue().dynamics().staticSolve(F);

  materials::MaterialSpec ms;
  ms.law = "linear";
  ms.params = {{"E", c.tissue.material.E}, {"nu", c.tissue.material.nu}};
  ms.density = c.tissue.material.density;
  auto ex = needlesim::testing::relaxingExplicitBlock(mesh, c.tissue.block, ms);
  for (int i = 0; i < 3; ++i) ex->setExternalForce(node, i, load[i]);
  ex->advanceTo(0.3);
  const auto& ue = ex->displacement();
  const double umax = u.cwiseAbs().maxCoeff();
  double worst = 0.0;
  for (int k = 0; k < u.size(); ++k) worst = std::max(worst, std::abs(u[k] - ue[static_cast<std::size_t>(k)]));
  std::printf("largest displacement %.4e m, largest difference %.4e m (%.3f%%)\n", umax, worst, 100 * worst / umax);
  EXPECT_GT(umax, 5e-6);
  EXPECT_LT(worst, 0.005 * umax);
}
