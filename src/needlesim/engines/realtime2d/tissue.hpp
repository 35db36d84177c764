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

#include "needlesim/engines/realtime2d/fe.hpp"
#include "needlesim/engines/realtime2d/mesh.hpp"
#include "needlesim/materials/material_spec.hpp"

namespace needlesim::realtime2d {

struct NewmarkParams {
  double gamma = 0.5;   // delta of eq 3.2
  double beta = 0.25;   // xi of eq 3.3 (average acceleration: unconditionally stable)
  bool unconditionallyStable() const { return gamma >= 0.5 && beta >= 0.25 * (gamma + 0.5) * (gamma + 0.5); }
};

struct NewmarkCoefficients {  // eq 3.4 written as A u = Q + M(...) + C(...)
  double dt = 0, a0 = 0, a1 = 0, a2 = 0, a3 = 0, a4 = 0, a5 = 0;
  NewmarkCoefficients() = default;
  NewmarkCoefficients(const NewmarkParams& p, double dt);
};

enum class Backend { Auto, Direct, Modal, Reduced };

// A disc of its own material (an inclusion's section in the insertion plane); the elements
// whose centre lies inside take its material. Mesh coordinates.
struct MaterialRegion {
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();  // m
  double radius = 0.0;                               // m
  ElasticMaterial material;                          // thickness and plane from TissueConfig::material
};

struct TissueConfig {
  ElasticMaterial material;
  MeshSpec mesh;
  bool lumped_mass = false;
  double rayleigh_alpha = 0.01;  // 1/s (seed 003 eq 3.8: alpha = 0.01)
  double rayleigh_beta = 0.1;    // s   (seed 003 eq 3.8: beta = 0.1)
  NewmarkParams newmark;
  // Boundary: all sides except the entry face held (seed 003 section 3.5 item 3),
  // or, with support_stiffness > 0, spring supports there instead (N/m^3: a
  // Winkler foundation per unit boundary area; node spring = k * tributary length * thickness).
  double support_stiffness = 0.0;
  // Layered block: materials by depth band (x of each band's far boundary, ascending);
  // when not empty it replaces `material` element by element (thickness from `material`).
  std::vector<std::pair<double, ElasticMaterial>> layers;
  // Material regions over the layers (bonded inclusions), in order: a later one wins.
  std::vector<MaterialRegion> regions;
  // Prony terms (materials/viscoelastic.hpp, seed 001 eqs 1-4): QLV relaxation of the whole
  // stiffness, K -> K G(t) with G = g_inf + sum g_i exp(-t/tau_i); empty = elastic.
  std::vector<materials::PronyTerm> prony;
  // Stiffening around the needle (seed 003 section 3.5 item 4): elements whose centre lies
  // within `stiffening_radius` of the path line have E times `stiffening_factor`.
  double stiffening_factor = 1.0;
  double stiffening_radius = 0.0;  // m
  Backend backend = Backend::Auto;
  int modal_max_dofs = 2600;  // Auto picks Modal up to this many free DOFs, Reduced above
  // Reduced: keep the modes below this frequency (rad/s; 0 = sqrt(20 / (beta dt))), at most
  // reduced_max_modes; the rest enter as residual flexibility with Rayleigh creep.
  double reduced_cutoff = 0.0;
  int reduced_max_modes = 400;
};

// Reference needle axis and the nodes on it.
struct PathNode {
  int node = 0;      // mesh node id
  double s = 0.0;    // m, reference position along the axis from the entry point
  double offset = 0; // m, lateral distance of the node from the axis line
};

class TissueIntegrator;

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
  Backend backend() const;
  double dt() const { return nm_.dt; }
  const NewmarkCoefficients& coefficients() const { return nm_; }
  void setTimeStep(double dt);  // refactorises (allocates); step sizes are normally constant

  // Path compliance S (2P x 2P): path displacement per unit path load within one step.
  const Eigen::MatrixXd& pathCompliance() const;
  void predict();                                  // fills predictedPath()
  const Eigen::VectorXd& predictedPath() const;    // u0_P (2P), t/n components
  void commit(const Eigen::VectorXd& f);           // f: 2P path loads (N)
  // Path state after the last commit (t/n components): u, v, a.
  const Eigen::VectorXd& pathU() const { return pu_; }
  const Eigen::VectorXd& pathV() const { return pv_; }
  const Eigen::VectorXd& pathA() const { return pa_; }
  // Full nodal displacement (2 * nodes; held DOFs 0). Modal back-end rebuilds it lazily.
  const Eigen::VectorXd& displacement() const;
  const Eigen::VectorXd& velocity() const;
  // Displacement of one node (held: 0) without rebuilding the full field.
  Eigen::Vector2d nodeDisplacement(int node) const;
  // Mean displacement of the nodes of a material region's elements (its material's motion).
  Eigen::Vector2d regionDisplacement(std::size_t region) const;
  // Centre stresses (sxx, syy, sxy, szz) of every element from displacement() (4 x elements);
  // szz = nu (sxx + syy) in plane strain, 0 in plane stress.
  Eigen::Matrix4Xd elementStresses() const;
  // Highest free-mesh frequency (rad/s) and the Newmark time-step limit it sets
  // (infinity when gamma/beta are unconditionally stable).
  double stableTimeStep() const { return dt_limit_; }

  // Energies of the current state (J): 0.5 v'Mv and 0.5 u'Ku.
  double kineticEnergy() const;
  double strainEnergy() const;
  // Sets the full state (2 * nodes vectors; held entries ignored); acceleration from
  // equilibrium with zero load: M a = -C v - K u.
  void setState(const Eigen::VectorXd& u, const Eigen::VectorXd& v);
  // Highest natural frequency (rad/s) of the free mesh, by power iteration.
  double highestFrequency() const;
  // Static solve K u = f (f full 2 * nodes); used by tests and relaxation.
  Eigen::VectorXd staticSolve(const Eigen::VectorXd& f) const;
  int freeDofs() const { return map_.freeCount(); }

 private:
  void assignMaterials(const Eigen::Vector2d& entry);
  void assembleSupported(const std::vector<bool>& onSides);
  void pickPath(const Eigen::Vector2d& entry, const std::vector<bool>& onSides);
  void makeIntegrator(double dt);
  void refreshFull() const;
  Mesh mesh_;
  TissueConfig cfg_;
  DofMap map_;
  Eigen::SparseMatrix<double> K_, M_;  // free DOFs (springs included in K)
  std::vector<PathNode> path_;
  std::vector<std::array<int, 2>> pdof_;  // free DOF of the x and y component of each path node (-1 held)
  Eigen::Vector2d t_, n_;
  NewmarkCoefficients nm_;
  std::unique_ptr<TissueIntegrator> impl_;
  Eigen::VectorXd pu_, pv_, pa_;
  Eigen::VectorXd u0P_;
  mutable Eigen::VectorXd full_u_, full_v_, fu_, fv_;
  mutable bool dirty_ = true;
  double dt_limit_ = 0.0;
  std::vector<ElasticMaterial> elem_mat_;
  std::vector<std::vector<int>> region_nodes_;  // nodes of each material region's elements
  std::vector<bool> held_;                      // per DOF
  void checkStable(double dt) const;
};

}  // namespace needlesim::realtime2d
