#pragma once
// Linear elastic 2D finite elements for the tissue (seed 003 eqs 3.5-3.11):
// bilinear quadrilaterals, 2 x 2 Gauss quadrature, K_e = sum B^T D B w det J t
// (eq 3.6), M_e = int N^T rho N dOmega t (eq 3.7), D of eq 3.9 with the Lame
// constants of eqs 3.10-3.11 (plane strain) or their plane-stress reduction.
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <vector>

#include "needlesim/engines/realtime/dof_map.hpp"
#include "needlesim/engines/realtime2d/mesh.hpp"

namespace needlesim::realtime2d {

struct ElasticMaterial {
  double E = 30.74e3;      // Pa
  double nu = 0.422;       // 1
  double density = 636.7;  // kg/m^3
  // m, out-of-plane extent carried by the 2D slab. Seed 003 eq 3.6 has no thickness factor (unit
  // thickness); its mm-size displacements under its ~0.3 N forces need mm units, so the thesis' own
  // model is a 1 mm slab. A 3D body of this gel moves 5-10x less (docs/validation/realtime2d.md).
  double thickness = 1e-3;
  bool plane_strain = true;  // eqs 3.9-3.11 are the plane-strain D (lambda + 2 mu on the diagonal)
};

// Elasticity matrix (eq 3.9); plane stress uses lambda* = 2 lambda mu / (lambda + 2 mu).
Eigen::Matrix3d elasticity(const ElasticMaterial& m);

// Element matrices of a 4-node quad with corner coordinates xy (2 x 4, counter-clockwise).
Eigen::Matrix<double, 8, 8> quadStiffness(const Eigen::Matrix<double, 2, 4>& xy, const Eigen::Matrix3d& D,
                                          double thickness);
Eigen::Matrix<double, 8, 8> quadMass(const Eigen::Matrix<double, 2, 4>& xy, double rho_t, bool lumped);
// Stress (sxx, syy, sxy) at the element centre from element displacements (8).
Eigen::Vector3d quadCentreStress(const Eigen::Matrix<double, 2, 4>& xy, const Eigen::Matrix3d& D,
                                 const Eigen::Matrix<double, 8, 1>& ue);

// Global stiffness and mass over all 2 * nodes DOFs (dof = 2 * node + component).
struct Assembled {
  Eigen::SparseMatrix<double> K, M;
};
Assembled assemble(const Mesh& mesh, const ElasticMaterial& mat, bool lumped_mass);
// One material per element (layered blocks).
Assembled assemble(const Mesh& mesh, const std::vector<ElasticMaterial>& per_element, bool lumped_mass);

// Free-DOF numbering (engines/realtime/dof_map.hpp), shared with realtime3d.
using realtime::DofMap;
using realtime::makeDofMap;
using realtime::restrictToFree;

// Boundary of the thesis (seed 003 section 3.5 assumption 3): every side except
// the entry face x = 0. Returns per-node flags.
std::vector<bool> nodesOnHeldSides(const Mesh& mesh);

}  // namespace needlesim::realtime2d
