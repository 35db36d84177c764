// Locating a marker's reference point in the explicit engine's mesh (marker_location.hpp).
#include "needlesim/engines/explicit/marker_location.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <vector>

namespace needlesim::explicit_fe {

namespace {

// Corner signs of the isoparametric quad4 (first four rows, z unused) and hex8, in the mesh's node order.
constexpr double kSign[8][3] = {{-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1},
                                {-1, -1, 1},  {1, -1, 1},  {1, 1, 1},  {-1, 1, 1}};

// Shape functions of a bilinear / trilinear element at natural coordinates xi (dim 2 or 3) and their
// derivatives dN[a](i) = dN_a / dxi_i.
void isoShape(int n, int dim, const Eigen::Vector3d& xi, double* N, Eigen::Vector3d* dN) {
  for (int a = 0; a < n; ++a) {
    double f[3] = {1, 1, 1};
    for (int i = 0; i < dim; ++i) f[i] = 0.5 * (1 + kSign[a][i] * xi[i]);
    N[a] = f[0] * f[1] * f[2];
    dN[a].setZero();
    for (int i = 0; i < dim; ++i) {
      double g = 0.5 * kSign[a][i];
      for (int j = 0; j < dim; ++j)
        if (j != i) g *= f[j];
      dN[a][i] = g;
    }
  }
}

// Natural coordinates of X in a quad4 / hex8 by Newton on the isoparametric map; the weights if X lies
// inside (|xi| <= 1 within round-off).
bool isoWeights(const std::vector<Eigen::Vector3d>& P, int dim, const Eigen::Vector3d& X, double* w) {
  const int n = static_cast<int>(P.size());
  Eigen::Vector3d xi = Eigen::Vector3d::Zero();
  double N[8];
  Eigen::Vector3d dN[8];
  for (int it = 0; it < 30; ++it) {
    isoShape(n, dim, xi, N, dN);
    Eigen::Vector3d r = -X;
    Eigen::Matrix3d J = Eigen::Matrix3d::Identity();
    J.topLeftCorner(dim, dim).setZero();
    for (int a = 0; a < n; ++a) {
      r += N[a] * P[static_cast<std::size_t>(a)];
      for (int i = 0; i < dim; ++i) J.col(i).head(dim) += dN[a][i] * P[static_cast<std::size_t>(a)].head(dim);
    }
    if (dim == 2) r.z() = 0.0;
    const Eigen::Vector3d step = J.fullPivLu().solve(r);
    xi -= step;
    if (step.norm() < 1e-12) break;
  }
  for (int i = 0; i < dim; ++i)
    if (!(std::abs(xi[i]) <= 1 + 1e-9)) return false;
  isoShape(n, dim, xi, N, dN);
  std::copy(N, N + n, w);
  return true;
}

// Barycentric weights of X in a tri3 / tet4, if inside.
bool simplexWeights(const std::vector<Eigen::Vector3d>& P, int dim, const Eigen::Vector3d& X, double* w) {
  Eigen::Matrix3d A = Eigen::Matrix3d::Identity();
  for (int i = 0; i < dim; ++i) A.col(i).head(dim) = (P[static_cast<std::size_t>(i) + 1] - P[0]).head(dim);
  Eigen::Vector3d rhs = X - P[0];
  if (dim == 2) rhs.z() = 0.0;
  const Eigen::Vector3d l = A.fullPivLu().solve(rhs);
  w[0] = 1.0 - l.head(dim).sum();
  for (int i = 0; i < dim; ++i) w[i + 1] = l[i];
  for (int a = 0; a <= dim; ++a)
    if (!(w[a] >= -1e-9)) return false;
  return true;
}

}  // namespace

std::optional<engines::MarkerPoint> locateMarker(const Mesh& mesh, const Eigen::Vector3d& X) {
  const int n = nodesPerElement(mesh.type), dim = mesh.dim;
  const bool iso = mesh.type == ElementType::Quad4 || mesh.type == ElementType::Hex8;
  std::vector<Eigen::Vector3d> P(static_cast<std::size_t>(n));
  for (int e = 0; e < mesh.elements(); ++e) {
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e300), hi = -lo;
    for (int a = 0; a < n; ++a) {
      const int node = mesh.conn[static_cast<std::size_t>(e) * n + a];
      P[static_cast<std::size_t>(a)].setZero();
      for (int i = 0; i < dim; ++i) P[static_cast<std::size_t>(a)][i] = mesh.coord(node, i);
      lo = lo.cwiseMin(P[static_cast<std::size_t>(a)]);
      hi = hi.cwiseMax(P[static_cast<std::size_t>(a)]);
    }
    const double tol = 1e-9 * (hi - lo).norm();
    bool inBox = true;
    for (int i = 0; i < dim; ++i) inBox = inBox && X[i] >= lo[i] - tol && X[i] <= hi[i] + tol;
    double w[8] = {};
    if (!inBox || !(iso ? isoWeights(P, dim, X, w) : simplexWeights(P, dim, X, w))) continue;
    engines::MarkerPoint m;
    for (int a = 0; a < n; ++a) {
      m.nodes[static_cast<std::size_t>(a)] = mesh.conn[static_cast<std::size_t>(e) * n + a];
      m.weights[static_cast<std::size_t>(a)] = w[a];
    }
    return m;
  }
  return std::nullopt;
}

}  // namespace needlesim::explicit_fe
