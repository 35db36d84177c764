#include "needlesim/engines/realtime3d/fe.hpp"

#include <Eigen/LU>
#include <cmath>
#include <limits>

#include "needlesim/core/error.hpp"
#include "needlesim/core/progress.hpp"
#include "needlesim/engines/realtime/dof_map.hpp"
#include "needlesim/materials/elastic_moduli.hpp"

namespace needlesim::realtime3d {

Matrix6d elasticity(const ElasticMaterial& m) {
  if (!(m.E > 0.0) || !(m.nu > -1.0 && m.nu < 0.5))
    throw SolverError("realtime3d: need E > 0 and -1 < nu < 0.5");
  const auto l = materials::lame(m.E, m.nu);
  Matrix6d D = Matrix6d::Zero();
  D.topLeftCorner<3, 3>().setConstant(l.lambda);
  for (int i = 0; i < 3; ++i) {
    D(i, i) += 2.0 * l.mu;
    D(3 + i, 3 + i) = l.mu;
  }
  return D;
}

double tetGradients(const Eigen::Matrix<double, 3, 4>& X, Eigen::Matrix<double, 3, 4>& dN) {
  Eigen::Matrix3d J;  // columns: edges from corner 0
  for (int a = 0; a < 3; ++a) J.col(a) = X.col(a + 1) - X.col(0);
  const double det = J.determinant();
  if (!(det > 0.0)) throw SolverError("realtime3d: degenerate or inverted tetrahedron");
  const Eigen::Matrix3d Jinv = J.inverse();  // rows: gradients of the barycentric coordinates 1..3
  for (int a = 0; a < 3; ++a) dN.col(a + 1) = Jinv.row(a).transpose();
  dN.col(0) = -(dN.col(1) + dN.col(2) + dN.col(3));
  return det / 6.0;
}

namespace {
Eigen::Matrix<double, 6, 12> strainDisplacement(const Eigen::Matrix<double, 3, 4>& dN) {
  Eigen::Matrix<double, 6, 12> B = Eigen::Matrix<double, 6, 12>::Zero();
  for (int a = 0; a < 4; ++a) {
    const double x = dN(0, a), y = dN(1, a), z = dN(2, a);
    B(0, 3 * a) = x; B(1, 3 * a + 1) = y; B(2, 3 * a + 2) = z;
    B(3, 3 * a + 1) = z; B(3, 3 * a + 2) = y;
    B(4, 3 * a) = z; B(4, 3 * a + 2) = x;
    B(5, 3 * a) = y; B(5, 3 * a + 1) = x;
  }
  return B;
}
}  // namespace

Matrix12d tetStiffness(const Eigen::Matrix<double, 3, 4>& X, const Matrix6d& D) {
  Eigen::Matrix<double, 3, 4> dN;
  const double V = tetGradients(X, dN);
  const auto B = strainDisplacement(dN);
  return V * B.transpose() * D * B;
}

Eigen::Matrix<double, 6, 1> tetStress(const Eigen::Matrix<double, 3, 4>& X, const Matrix6d& D,
                                      const Eigen::Matrix<double, 12, 1>& ue) {
  Eigen::Matrix<double, 3, 4> dN;
  tetGradients(X, dN);
  return D * (strainDisplacement(dN) * ue);
}

double vonMises(const Eigen::Matrix<double, 6, 1>& s) {
  const double a = s[0] - s[1], b = s[1] - s[2], c = s[2] - s[0];
  return std::sqrt(0.5 * (a * a + b * b + c * c) + 3.0 * (s[3] * s[3] + s[4] * s[4] + s[5] * s[5]));
}

Eigen::Matrix<double, 3, 4> tetCorners(const TetMesh& mesh, int e) {
  Eigen::Matrix<double, 3, 4> X;
  for (int a = 0; a < 4; ++a) {
    const int n = mesh.conn[static_cast<std::size_t>(4 * e + a)];
    for (int q = 0; q < 3; ++q) X(q, a) = mesh.coord(n, q);
  }
  return X;
}

Eigen::Vector3d tetCentre(const TetMesh& mesh, int e) { return tetCorners(mesh, e).rowwise().mean(); }

Eigen::Vector4d tetShapeFunctions(const Eigen::Matrix<double, 3, 4>& X, const Eigen::Vector3d& p) {
  Eigen::Matrix<double, 3, 4> dN;
  tetGradients(X, dN);
  const Eigen::Vector3d centre = X.rowwise().mean();
  return Eigen::Vector4d::Constant(0.25) + dN.transpose() * (p - centre);
}

TetPoint locateInTets(const TetMesh& mesh, const Eigen::Vector3d& p) {
  TetPoint best;
  double bestMin = -std::numeric_limits<double>::infinity();
  for (int e = 0; e < mesh.elements(); ++e) {
    const auto X = tetCorners(mesh, e);
    const double pad = 1e-9 * (X.rowwise().maxCoeff() - X.rowwise().minCoeff()).norm();
    if (((p - X.rowwise().minCoeff()).array() < -pad).any() || ((X.rowwise().maxCoeff() - p).array() < -pad).any())
      continue;
    const Eigen::Vector4d N = tetShapeFunctions(X, p);
    if (N.minCoeff() > bestMin) {
      bestMin = N.minCoeff();
      best = {e, N};
    }
  }
  return best;
}

Assembled assemble(const TetMesh& mesh, const std::vector<ElasticMaterial>& mats, bool lumped_mass) {
  if (mats.size() != static_cast<std::size_t>(mesh.elements()))
    throw SolverError("realtime3d: one material per element expected");
  std::vector<Eigen::Triplet<double>> tk, tm;
  tk.reserve(static_cast<std::size_t>(mesh.elements()) * 144);
  tm.reserve(static_cast<std::size_t>(mesh.elements()) * (lumped_mass ? 12 : 48));
  for (int e = 0; e < mesh.elements(); ++e) {
    if ((e & 4095) == 0) throwIfStopRequested("realtime3d: assembling the tissue");
    const auto& mat = mats[static_cast<std::size_t>(e)];
    if (!(mat.density > 0.0)) throw SolverError("realtime3d: need density > 0");
    const auto X = tetCorners(mesh, e);
    Eigen::Matrix<double, 3, 4> dN;
    const double V = tetGradients(X, dN);
    const Matrix12d Ke = tetStiffness(X, elasticity(mat));
    auto dof = [&](int a) { return 3 * mesh.conn[static_cast<std::size_t>(4 * e + a / 3)] + a % 3; };
    for (int a = 0; a < 12; ++a)
      for (int b = 0; b < 12; ++b) tk.emplace_back(dof(a), dof(b), Ke(a, b));
    for (int a = 0; a < 12; ++a)
      for (int b = a % 3; b < 12; b += 3) {  // same component only
        const double m = lumped_mass ? (a == b ? 0.25 : 0.0) : (a == b ? 0.1 : 0.05);
        if (m != 0.0) tm.emplace_back(dof(a), dof(b), m * mat.density * V);
      }
  }
  const int n = 3 * mesh.nodes();
  return {realtime::sparseFrom(n, tk), realtime::sparseFrom(n, tm)};
}

}  // namespace needlesim::realtime3d
