#pragma once
// Tissue dynamics shared by the real-time engines (realtime2d, realtime3d):
// M u'' + C u' + K u = Q (seed 003 eq 3.1) with Rayleigh damping C = alpha M + beta K
// (eq 3.8) and Newmark integration (eqs 3.2-3.4) on the free DOFs of an assembled mesh.
// All loads act on a fixed set of "path" nodes (the nodes the needle can couple to),
// each with comps() load directions (axial t first, then the lateral ones). A step is split in two:
//   predict():  u0_P, the path displacements the step would give without path loads;
//   commit(f):  apply path loads f (comps() per path node) and advance the state.
// Between the two, pathCompliance() S gives u_P = u0_P + S f exactly, so the needle
// coupling is solved on the path nodes only (a Schur complement, eqs 3.20-3.21).
// Back-ends (tissue_integrators.hpp): Direct, Modal (all modes), Reduced (lowest modes
// plus residual flexibility; O((modes + path DOFs) * path DOFs) per step).
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <memory>
#include <string>
#include <vector>

#include "needlesim/engines/realtime/dof_map.hpp"
#include "needlesim/engines/realtime/newmark.hpp"
#include "needlesim/materials/viscoelastic.hpp"

namespace needlesim::realtime {

class TissueIntegrator;
struct PathMap;

// The state a full displacement field is rebuilt from (TissueDynamics::saveDisplacement):
// the direct back-end's displacement on the free DOFs, the modal coordinates, and for the
// reduced back-end also the filtered path loads of its residual modes.
struct DisplacementState {
  Eigen::VectorXd coordinates;  // direct: u on the free DOFs; modal, reduced: q
  Eigen::VectorXd residual;     // reduced: the residual filter g (path loads); empty otherwise
};

// Damping, integration and back-end settings of a real-time tissue.
struct DynamicsSettings {
  bool lumped_mass = false;
  double rayleigh_alpha = 0.01;  // 1/s (seed 003 eq 3.8: alpha = 0.01)
  double rayleigh_beta = 0.1;    // s   (seed 003 eq 3.8: beta = 0.1)
  NewmarkParams newmark;
  // Prony terms (materials/viscoelastic.hpp, seed 001 eqs 1-4): QLV relaxation of the whole
  // stiffness, K -> K G(t) with G = g_inf + sum g_i exp(-t/tau_i); empty = elastic.
  std::vector<materials::PronyTerm> prony;
  Backend backend = Backend::Auto;
  int modal_max_dofs = 2600;  // Auto picks Modal up to this many free DOFs, Reduced above
  // Reduced: keep the modes below this frequency (rad/s; 0 = sqrt(20 / (beta dt))), at most
  // reduced_max_modes; the rest enter as residual flexibility with Rayleigh creep.
  double reduced_cutoff = 0.0;
  int reduced_max_modes = 400;
};

// The assembled tissue and its path: K, M over all dim * nodes DOFs, held DOFs, the path
// points (tissue_integrators.hpp PathMap): each a mesh node, or with path_start a weighted set
// of mesh nodes (path_nodes[path_start[i] .. path_start[i+1]), weights path_weights);
// dirs (dim x comps) the directions of the path loads.
struct PathedSystem {
  Eigen::SparseMatrix<double> K, M;
  std::vector<bool> held;       // per DOF
  std::vector<int> path_nodes;  // mesh node ids
  int dim = 2;
  Eigen::MatrixXd dirs;
  std::vector<int> path_start;        // empty: one node per path point
  std::vector<double> path_weights;   // per entry of path_nodes (with path_start)
};

class TissueDynamics {
 public:
  TissueDynamics(std::string engine, const DynamicsSettings& cfg, const PathedSystem& sys, double dt);
  ~TissueDynamics();
  TissueDynamics(TissueDynamics&&) noexcept;
  TissueDynamics& operator=(TissueDynamics&&) noexcept;

  int pathDofs() const { return comps_ * points_; }
  Backend backend() const;
  double dt() const { return nm_.dt; }
  const NewmarkCoefficients& coefficients() const { return nm_; }
  void setTimeStep(double dt);  // refactorises (allocates); step sizes are normally constant
  const Eigen::MatrixXd& pathCompliance() const;
  void predict();
  const Eigen::VectorXd& predictedPath() const { return u0P_; }
  void commit(const Eigen::VectorXd& f);
  const Eigen::VectorXd& pathU() const { return pu_; }
  const Eigen::VectorXd& pathV() const { return pv_; }
  const Eigen::VectorXd& pathA() const { return pa_; }
  // Full nodal fields (dim * nodes; held DOFs 0), each rebuilt lazily on its own.
  const Eigen::VectorXd& displacement() const;
  const Eigen::VectorXd& velocity() const;
  // The displacement in two parts, for a reader in another thread: saveDisplacement copies the
  // small state it is rebuilt from (tissue_integrators.hpp; no allocation once `state` is
  // sized), displacementFrom rebuilds the full field from it, reading only what stepping never
  // changes (mode shapes, path flexibility, DOF map), so it may run while this tissue steps.
  void saveDisplacement(DisplacementState& state) const;
  void displacementFrom(const DisplacementState& state, Eigen::VectorXd& full) const;
  double dofDisplacement(int dof) const;  // one DOF without rebuilding the full field
  double kineticEnergy() const;
  double strainEnergy() const;
  void setState(const Eigen::VectorXd& u, const Eigen::VectorXd& v);
  // Moves path point i (of weighted entries, path_start) onto other mesh nodes before it takes
  // any load: its path flexibility from the existing factorisation or basis (a few solves), its
  // path state from the current fields (the acceleration there taken as zero: a slow insertion).
  void movePathPoint(int i, const std::vector<int>& nodes, const std::vector<double>& weights);
  double highestFrequency() const;
  Eigen::VectorXd staticSolve(const Eigen::VectorXd& f) const;
  int freeDofs() const { return map_.freeCount(); }
  double stableTimeStep() const { return dt_limit_; }
  const DofMap& dofMap() const { return map_; }

 private:
  void makeIntegrator(double dt);
  void checkStable(double dt) const;
  void refreshDisplacement() const;
  void refreshVelocity() const;
  void scatterFree(const Eigen::VectorXd& free, Eigen::VectorXd& full) const;
  PathMap pathMap() const;
  std::string engine_;
  DynamicsSettings cfg_;
  DofMap map_;
  Eigen::SparseMatrix<double> K_, M_;  // free DOFs
  std::vector<int> pdof_;              // free DOF of each spatial component of each path entry
  std::vector<int> pstart_;            // path point -> its entries (empty: one each)
  std::vector<double> pweight_;        // weight of each entry
  int dim_ = 2, comps_ = 2, points_ = 0;
  Eigen::MatrixXd dirs_;
  NewmarkCoefficients nm_;
  std::unique_ptr<TissueIntegrator> impl_;
  Eigen::VectorXd pu_, pv_, pa_, u0P_, uP_;
  mutable Eigen::VectorXd full_u_, full_v_, fu_, fv_;
  mutable bool displacementStale_ = true, velocityStale_ = true;
  double dt_limit_ = 0.0;
};

}  // namespace needlesim::realtime
