#include "needlesim/engines/realtime2d/fe.hpp"

#include <Eigen/LU>
#include <cmath>

#include "needlesim/core/error.hpp"
#include "needlesim/core/progress.hpp"
#include "needlesim/materials/elastic_moduli.hpp"

namespace needlesim::realtime2d {

namespace {
constexpr double kGauss = 0.57735026918962576451;  // 1/sqrt(3)
const double kXi[4] = {-1, 1, 1, -1};
const double kEta[4] = {-1, -1, 1, 1};

// Shape function derivatives w.r.t. global coordinates (2 x 4) and det J at (xi, eta).
double shapeGradients(const Eigen::Matrix<double, 2, 4>& xy, double xi, double eta,
                      Eigen::Matrix<double, 2, 4>& dN) {
  Eigen::Matrix<double, 2, 4> dRef;
  for (int a = 0; a < 4; ++a) {
    dRef(0, a) = 0.25 * kXi[a] * (1 + kEta[a] * eta);
    dRef(1, a) = 0.25 * kEta[a] * (1 + kXi[a] * xi);
  }
  const Eigen::Matrix2d J = dRef * xy.transpose();  // J(r, c) = d x_c / d xi_r
  const double det = J.determinant();
  if (!(det > 0.0)) throw SolverError("realtime2d: degenerate or inverted quadrilateral element");
  dN = J.inverse() * dRef;
  return det;
}

Eigen::Matrix<double, 3, 8> strainDisplacement(const Eigen::Matrix<double, 2, 4>& dN) {
  Eigen::Matrix<double, 3, 8> B = Eigen::Matrix<double, 3, 8>::Zero();
  for (int a = 0; a < 4; ++a) {
    B(0, 2 * a) = dN(0, a);
    B(1, 2 * a + 1) = dN(1, a);
    B(2, 2 * a) = dN(1, a);
    B(2, 2 * a + 1) = dN(0, a);
  }
  return B;
}
}  // namespace

Eigen::Matrix3d elasticity(const ElasticMaterial& m) {
  if (!(m.E > 0.0) || !(m.nu > -1.0 && m.nu < 0.5))
    throw SolverError("realtime2d: need E > 0 and -1 < nu < 0.5 for linear elastic tissue");
  auto [lambda, mu] = materials::lame(m.E, m.nu);  // eqs 3.10-3.11
  if (!m.plane_strain) lambda = 2.0 * lambda * mu / (lambda + 2.0 * mu);
  Eigen::Matrix3d D;
  D << lambda + 2 * mu, lambda, 0, lambda, lambda + 2 * mu, 0, 0, 0, mu;  // eq 3.9
  return D;
}

Eigen::Matrix<double, 8, 8> quadStiffness(const Eigen::Matrix<double, 2, 4>& xy, const Eigen::Matrix3d& D,
                                          double thickness) {
  Eigen::Matrix<double, 8, 8> K = Eigen::Matrix<double, 8, 8>::Zero();
  Eigen::Matrix<double, 2, 4> dN;
  for (int g = 0; g < 4; ++g) {
    const double det = shapeGradients(xy, kXi[g] * kGauss, kEta[g] * kGauss, dN);
    const auto B = strainDisplacement(dN);
    K.noalias() += B.transpose() * D * B * (det * thickness);  // eq 3.6, weights 1
  }
  return K;
}

Eigen::Matrix<double, 8, 8> quadMass(const Eigen::Matrix<double, 2, 4>& xy, double rho_t, bool lumped) {
  Eigen::Matrix<double, 8, 8> M = Eigen::Matrix<double, 8, 8>::Zero();
  Eigen::Matrix<double, 2, 4> dN;
  for (int g = 0; g < 4; ++g) {
    const double xi = kXi[g] * kGauss, eta = kEta[g] * kGauss;
    const double det = shapeGradients(xy, xi, eta, dN);
    Eigen::Vector4d N;
    for (int a = 0; a < 4; ++a) N(a) = 0.25 * (1 + kXi[a] * xi) * (1 + kEta[a] * eta);
    const Eigen::Matrix4d m = N * N.transpose() * (rho_t * det);  // eq 3.7
    for (int a = 0; a < 4; ++a)
      for (int b = 0; b < 4; ++b) {
        M(2 * a, 2 * b) += m(a, b);
        M(2 * a + 1, 2 * b + 1) += m(a, b);
      }
  }
  if (lumped) {  // row-sum lumping (exact total mass, positive for bilinear quads)
    for (int r = 0; r < 8; ++r) {
      const double s = M.row(r).sum();
      M.row(r).setZero();
      M(r, r) = s;
    }
  }
  return M;
}

Eigen::Vector3d quadCentreStress(const Eigen::Matrix<double, 2, 4>& xy, const Eigen::Matrix3d& D,
                                 const Eigen::Matrix<double, 8, 1>& ue) {
  Eigen::Matrix<double, 2, 4> dN;
  shapeGradients(xy, 0.0, 0.0, dN);
  return D * (strainDisplacement(dN) * ue);
}

Assembled assemble(const Mesh& mesh, const ElasticMaterial& mat, bool lumped_mass) {
  return assemble(mesh, std::vector<ElasticMaterial>(static_cast<std::size_t>(mesh.elementCount()), mat), lumped_mass);
}

Assembled assemble(const Mesh& mesh, const std::vector<ElasticMaterial>& mats, bool lumped_mass) {
  if (mats.size() != static_cast<std::size_t>(mesh.elementCount()))
    throw SolverError("realtime2d: one material per element expected");
  std::vector<Eigen::Triplet<double>> tk, tm;
  tk.reserve(static_cast<std::size_t>(mesh.elementCount()) * 64);
  tm.reserve(static_cast<std::size_t>(mesh.elementCount()) * 64);
  for (int e = 0; e < mesh.elementCount(); ++e) {
    if ((e & 4095) == 0) throwIfStopRequested("realtime2d: assembling the tissue");
    const auto& mat = mats[static_cast<std::size_t>(e)];
    const Eigen::Matrix3d D = elasticity(mat);
    if (!(mat.thickness > 0.0) || !(mat.density > 0.0))
      throw SolverError("realtime2d: need thickness > 0 and density > 0");
    Eigen::Matrix<double, 2, 4> xy;
    for (int a = 0; a < 4; ++a) xy.col(a) = mesh.nodes.col(mesh.quads(a, e));
    const auto Ke = quadStiffness(xy, D, mat.thickness);
    const auto Me = quadMass(xy, mat.density * mat.thickness, lumped_mass);
    for (int a = 0; a < 8; ++a)
      for (int b = 0; b < 8; ++b) {
        const int r = 2 * mesh.quads(a / 2, e) + a % 2, c = 2 * mesh.quads(b / 2, e) + b % 2;
        tk.emplace_back(r, c, Ke(a, b));
        if (Me(a, b) != 0.0) tm.emplace_back(r, c, Me(a, b));
      }
  }
  const int n = 2 * mesh.nodeCount();
  return {realtime::sparseFrom(n, tk), realtime::sparseFrom(n, tm)};
}

std::vector<bool> nodesOnHeldSides(const Mesh& mesh) {
  std::vector<bool> held(static_cast<std::size_t>(mesh.nodeCount()), false);
  for (int i = 0; i < mesh.nx; ++i)
    for (int j = 0; j < mesh.ny; ++j)
      if (i == mesh.nx - 1 || j == 0 || j == mesh.ny - 1) held[static_cast<std::size_t>(mesh.node(i, j))] = true;
  return held;
}

}  // namespace needlesim::realtime2d
