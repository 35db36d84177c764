// Linear tetrahedra of realtime3d (engines/realtime3d/fe.hpp): the patch test and the mass.
#include <gtest/gtest.h>

#include <Eigen/Dense>

#include "needlesim/engines/realtime2d/mesh.hpp"
#include "needlesim/engines/realtime3d/fe.hpp"

using namespace needlesim::realtime3d;

namespace {
TetMesh gradedBlock() {
  const auto ys = needlesim::realtime2d::gradedCoordinates(0.03, 0.012, 7, 4.0);
  return needlesim::explicit_fe::structuredBlock({0.0, 0.004, 0.01, 0.02}, ys, {0.0, 0.01, 0.013, 0.03},
                                                  needlesim::explicit_fe::ElementType::Tet4);
}
}  // namespace

// Patch test: a linear displacement field (constant strain) is reproduced exactly, so K u has no
// force at interior nodes, and the energy 1/2 u'Ku equals the constant strain energy times the volume.
TEST(Realtime3dFe, LinearFieldPassesThePatchTest) {
  const TetMesh m = gradedBlock();
  const ElasticMaterial mat{30e3, 0.45, 1000.0};
  const auto a = assemble(m, std::vector<ElasticMaterial>(static_cast<std::size_t>(m.elements()), mat), false);
  Eigen::Matrix3d G;
  G << 1e-3, 2e-4, -3e-4, 5e-4, -2e-3, 1e-4, 0.0, 7e-4, 1.5e-3;
  Eigen::VectorXd u(3 * m.nodes());
  for (int n = 0; n < m.nodes(); ++n) u.segment<3>(3 * n) = G * Eigen::Vector3d(m.coord(n, 0), m.coord(n, 1), m.coord(n, 2));
  const Eigen::VectorXd f = a.K * u;
  double interior = 0.0, scale = f.cwiseAbs().maxCoeff();
  for (int n = 0; n < m.nodes(); ++n) {
    const double x = m.coord(n, 0), y = m.coord(n, 1), z = m.coord(n, 2);
    if (x > 1e-9 && x < 0.02 - 1e-9 && y > 1e-9 && y < 0.03 - 1e-9 && z > 1e-9 && z < 0.03 - 1e-9)
      interior = std::max(interior, f.segment<3>(3 * n).cwiseAbs().maxCoeff());
  }
  EXPECT_LT(interior, 1e-10 * scale);
  const Eigen::Matrix3d eps = 0.5 * (G + G.transpose());
  const Matrix6d D = elasticity(mat);
  Eigen::Matrix<double, 6, 1> e;
  e << eps(0, 0), eps(1, 1), eps(2, 2), 2 * eps(1, 2), 2 * eps(0, 2), 2 * eps(0, 1);
  const double V = 0.02 * 0.03 * 0.03;
  EXPECT_NEAR(0.5 * u.dot(f), 0.5 * e.dot(D * e) * V, 1e-9 * e.dot(D * e) * V);
}

// The consistent and lumped mass matrices both carry the block's mass in each direction.
TEST(Realtime3dFe, MassMatricesCarryTheBlocksMass) {
  const TetMesh m = gradedBlock();
  const ElasticMaterial mat{30e3, 0.45, 1000.0};
  const std::vector<ElasticMaterial> mats(static_cast<std::size_t>(m.elements()), mat);
  for (bool lumped : {false, true}) {
    const auto a = assemble(m, mats, lumped);
    Eigen::VectorXd ex = Eigen::VectorXd::Zero(3 * m.nodes());
    for (int n = 0; n < m.nodes(); ++n) ex[3 * n] = 1.0;
    EXPECT_NEAR(ex.dot(a.M * ex), 1000.0 * 0.02 * 0.03 * 0.03, 1e-12) << "lumped " << lumped;
  }
}
