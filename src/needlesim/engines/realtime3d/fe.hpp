#pragma once
// Linear elastic 3D finite elements of the realtime3d tissue: 4-node tetrahedra
// (constant strain), the 3D form of seed 003 eqs 3.5-3.11: K_e = V B^T D B (eq 3.6 with
// one-point integration, exact for linear tets), M_e = int N^T rho N dV (eq 3.7: consistent
// rho V / 20 (1 + delta_ab), or lumped rho V / 4), D the isotropic elasticity with the Lame
// constants of eqs 3.10-3.11.
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <vector>

#include "needlesim/engines/explicit/mesh.hpp"

namespace needlesim::realtime3d {

using TetMesh = explicit_fe::Mesh;  // Tet4, node-interleaved coordinates (engines/explicit/mesh.hpp)

struct ElasticMaterial {
  double E = 30.74e3;      // Pa
  double nu = 0.422;       // 1
  double density = 636.7;  // kg/m^3
};

using Matrix6d = Eigen::Matrix<double, 6, 6>;
using Matrix12d = Eigen::Matrix<double, 12, 12>;
// Voigt order xx, yy, zz, yz, xz, xy (engineering shear strains).
Matrix6d elasticity(const ElasticMaterial& m);
// Shape-function gradients (3 x 4) of a tet with corners X (3 x 4); returns its volume (> 0).
double tetGradients(const Eigen::Matrix<double, 3, 4>& X, Eigen::Matrix<double, 3, 4>& dN);
Matrix12d tetStiffness(const Eigen::Matrix<double, 3, 4>& X, const Matrix6d& D);
// Element stress (Voigt) from element displacements (12, node-interleaved).
Eigen::Matrix<double, 6, 1> tetStress(const Eigen::Matrix<double, 3, 4>& X, const Matrix6d& D,
                                      const Eigen::Matrix<double, 12, 1>& ue);
double vonMises(const Eigen::Matrix<double, 6, 1>& s);

Eigen::Matrix<double, 3, 4> tetCorners(const TetMesh& mesh, int e);
Eigen::Vector3d tetCentre(const TetMesh& mesh, int e);

// Linear shape functions of a tet at a point (its barycentric coordinates, eq 3.5):
// N_a(p) = 1/4 + grad N_a . (p - centre).
Eigen::Vector4d tetShapeFunctions(const Eigen::Matrix<double, 3, 4>& X, const Eigen::Vector3d& p);
// The tet holding point p (of those whose bounding box holds it, the one whose smallest
// shape function at p is largest: on a shared face or node any holder) and the shape
// functions there. -1 and zeros when no tet's bounding box holds p.
struct TetPoint {
  int element = -1;
  Eigen::Vector4d weights = Eigen::Vector4d::Zero();
};
TetPoint locateInTets(const TetMesh& mesh, const Eigen::Vector3d& p);

struct Assembled {
  Eigen::SparseMatrix<double> K, M;  // 3 * nodes DOFs, dof = 3 * node + component
};
Assembled assemble(const TetMesh& mesh, const std::vector<ElasticMaterial>& per_element, bool lumped_mass);

}  // namespace needlesim::realtime3d
