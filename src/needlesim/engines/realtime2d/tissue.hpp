#pragma once
// Tissue dynamics of the real-time 2D engine: M u'' + C u' + K u = Q (seed 003
// eq 3.1) with Rayleigh damping C = alpha M + beta K (eq 3.8) and Newmark
// integration (eqs 3.2-3.4). All loads act on a fixed set of "path" nodes (the
// nodes the needle can couple to), each with two directions: axial t and
// lateral n of the reference needle axis. A step is split in two:
//   predict():  u0_P, the path displacements the step would give without path loads;
//   commit(f):  apply path loads f (2 per path node: t then n) and advance the state.
// Between the two, pathCompliance() S gives u_P = u0_P + S f exactly, so the needle
// coupling is solved on the path nodes only (a Schur complement, eq 3.20-3.21).
//
// Two exact back-ends of the same Newmark scheme:
//   Direct: sparse LDLT of the effective matrix A = K + a0 M + a1 C, factorised once
//           per time step size; one sparse solve per step plus Z f with Z = A^-1 G.
//   Modal:  generalised eigenvectors K phi = w^2 M phi (all of them); with Rayleigh
//           damping A, M, C, K are all diagonal in this basis, so Newmark is the same
//           algorithm mode by mode; a step costs O(n * path DOFs); the full field is
//           rebuilt (u = Phi q) only when asked for.
//   Reduced: the lowest modes (shift-invert Lanczos) as in Modal, plus the residual
//           flexibility of all other modes on the path DOFs, which creep with the
//           Rayleigh time constant beta (their inertia is negligible); exact statics,
//           O((modes + path DOFs) * path DOFs) per step. For 10k-node meshes.
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <array>
#include <memory>
#include <vector>

#include "needlesim/engines/realtime/tissue_dynamics.hpp"
#include "needlesim/engines/realtime2d/fe.hpp"
#include "needlesim/engines/realtime2d/mesh.hpp"
#include "needlesim/scenario/scenario.hpp"
#include "needlesim/materials/material_spec.hpp"

namespace needlesim::realtime2d {

using realtime::Backend;
using realtime::NewmarkCoefficients;
using realtime::NewmarkParams;

// A disc of its own material (an inclusion's section in the insertion plane); the elements
// whose centre lies inside take its material. Mesh coordinates.
struct MaterialRegion {
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();  // m
  double radius = 0.0;                               // m
  ElasticMaterial material;                          // thickness and plane from TissueConfig::material
};

// Damping, Newmark, Prony and back-end settings: realtime::DynamicsSettings.
struct TissueConfig : realtime::DynamicsSettings {
  ElasticMaterial material;
  MeshSpec mesh;
  // Boundary: all sides except the entry face held (seed 003 section 3.5 item 3),
  // or, with support_stiffness > 0, spring supports there instead (N/m^3: a
  // Winkler foundation per unit boundary area; node spring = k * tributary length * thickness).
  double support_stiffness = 0.0;
  // Layered block: materials by depth band (x of each band's far boundary, ascending);
  // when not empty it replaces `material` element by element (thickness from `material`).
  std::vector<std::pair<double, ElasticMaterial>> layers;
  // Material regions over the layers (bonded inclusions), in order: a later one wins.
  std::vector<MaterialRegion> regions;
  // Stiffening around the needle (seed 003 section 3.5 item 4): elements whose centre lies
  // within `stiffening_radius` of the path line have E times `stiffening_factor`.
  double stiffening_factor = 1.0;
  double stiffening_radius = 0.0;  // m
  // Imported 2D mesh (tissue.geometry, imported_mesh.hpp): replaces `mesh`; elements take the
  // material of their region (one layer: `material`; inclusion i: regions[i].material), the
  // held nodes are its supported far side and the sides facing across the path.
  std::shared_ptr<const ImportedGeometry> geometry;
};


class Tissue {
 public:
  Tissue(const TissueConfig& cfg, const Eigen::Vector2d& entry, const Eigen::Vector2d& axis, double dt);
  ~Tissue();
  Tissue(Tissue&&) noexcept;
  Tissue& operator=(Tissue&&) noexcept;

  const Mesh& mesh() const { return mesh_; }
  const std::vector<PathNode>& path() const { return path_; }
  int pathDofs() const { return 2 * static_cast<int>(path_.size()); }
  const Eigen::Vector2d& axis() const { return t_; }
  const Eigen::Vector2d& normal() const { return n_; }
  Backend backend() const { return dyn_->backend(); }
  double dt() const { return dyn_->dt(); }
  const NewmarkCoefficients& coefficients() const { return dyn_->coefficients(); }
  void setTimeStep(double dt) { dyn_->setTimeStep(dt); }  // refactorises (allocates); step sizes are normally constant

  // Path compliance S (2P x 2P): path displacement per unit path load within one step.
  const Eigen::MatrixXd& pathCompliance() const { return dyn_->pathCompliance(); }
  void predict() { dyn_->predict(); }              // fills predictedPath()
  const Eigen::VectorXd& predictedPath() const { return dyn_->predictedPath(); }  // u0_P (2P), t/n
  void commit(const Eigen::VectorXd& f) { dyn_->commit(f); }  // f: 2P path loads (N)
  // Path state after the last commit (t/n components): u, v, a.
  const Eigen::VectorXd& pathU() const { return dyn_->pathU(); }
  const Eigen::VectorXd& pathV() const { return dyn_->pathV(); }
  const Eigen::VectorXd& pathA() const { return dyn_->pathA(); }
  // Full nodal displacement (2 * nodes; held DOFs 0). Modal back-end rebuilds it lazily.
  const Eigen::VectorXd& displacement() const { return dyn_->displacement(); }
  const Eigen::VectorXd& velocity() const { return dyn_->velocity(); }
  // Displacement of one node (held: 0) without rebuilding the full field.
  Eigen::Vector2d nodeDisplacement(int node) const;
  // Mean displacement of the nodes of a material region's elements (its material's motion).
  Eigen::Vector2d regionDisplacement(std::size_t region) const;
  // Those nodes (indices of the mesh's nodes).
  const std::vector<int>& regionNodes(std::size_t region) const { return region_nodes_.at(region); }
  // Centre stresses (sxx, syy, sxy, szz) of every element from displacement() (4 x elements);
  // szz = nu (sxx + syy) in plane strain, 0 in plane stress.
  Eigen::Matrix4Xd elementStresses() const;
  // Highest free-mesh frequency (rad/s) and the Newmark time-step limit it sets
  // (infinity when gamma/beta are unconditionally stable).
  double stableTimeStep() const { return dyn_->stableTimeStep(); }

  // Energies of the current state (J): 0.5 v'Mv and 0.5 u'Ku.
  double kineticEnergy() const { return dyn_->kineticEnergy(); }
  double strainEnergy() const { return dyn_->strainEnergy(); }
  // Sets the full state (2 * nodes vectors; held entries ignored); acceleration from
  // equilibrium with zero load: M a = -C v - K u.
  void setState(const Eigen::VectorXd& u, const Eigen::VectorXd& v) { dyn_->setState(u, v); }
  // Highest natural frequency (rad/s) of the free mesh, by power iteration.
  double highestFrequency() const { return dyn_->highestFrequency(); }
  // Static solve K u = f (f full 2 * nodes); used by tests and relaxation.
  Eigen::VectorXd staticSolve(const Eigen::VectorXd& f) const { return dyn_->staticSolve(f); }
  int freeDofs() const { return dyn_->freeDofs(); }
  const realtime::TissueDynamics& dynamics() const { return *dyn_; }

 private:
  void assignMaterials(const Eigen::Vector2d& entry);
  realtime::PathedSystem assembleSupported(const std::vector<bool>& onSides);
  void pickPath(const Eigen::Vector2d& entry, const std::vector<bool>& onSides);
  Mesh mesh_;
  TissueConfig cfg_;
  std::vector<PathNode> path_;
  Eigen::Vector2d t_, n_;
  std::unique_ptr<realtime::TissueDynamics> dyn_;
  std::vector<ElasticMaterial> elem_mat_;
  std::vector<std::vector<int>> region_nodes_;  // nodes of each material region's elements
  std::vector<bool> held_;                      // per DOF
};

}  // namespace needlesim::realtime2d
