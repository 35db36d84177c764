#pragma once
// The Newmark back-ends of the real-time tissues (realtime2d, realtime3d; tissue_dynamics.hpp):
// direct sparse LDLT, modal (all modes) and reduced (lowest modes plus residual flexibility),
// behind one interface, on the free DOFs of any mesh.
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <memory>
#include <vector>

#include "needlesim/engines/realtime/newmark.hpp"
#include "needlesim/engines/realtime/tissue_dynamics.hpp"
#include "needlesim/materials/viscoelastic.hpp"

namespace needlesim::realtime {

// The path loads' placement on the free DOFs. Path point i spreads over entries
// start[i] .. start[i+1] (without `start`: entry i alone), entry e a mesh node with `dim`
// spatial DOFs (dofs[dim e + d], -1 when held) and weight weights[e] (without `weights`: 1):
// a mesh node (realtime2d) or a point embedded in the elements (realtime3d, interpolation
// weights). comps() load components per point, component c acting along dirs.col(c) (axial
// first, then the lateral directions). Path load k = comps() i + c; its displacement is the
// same weighted sum of the entries' displacements (the transpose of the load's spreading).
struct PathMap {
  const std::vector<int>* dofs = nullptr;
  int dim = 2;
  Eigen::MatrixXd dirs;  // dim x comps
  const std::vector<int>* start = nullptr;
  const std::vector<double>* weights = nullptr;
  int comps() const { return static_cast<int>(dirs.cols()); }
  int nodes() const { return start ? static_cast<int>(start->size()) - 1 : static_cast<int>(dofs->size()) / dim; }
  int size() const { return comps() * nodes(); }
  int first(int i) const { return start ? (*start)[static_cast<std::size_t>(i)] : i; }
  int last(int i) const { return start ? (*start)[static_cast<std::size_t>(i + 1)] : i + 1; }
  double weight(int e) const { return weights ? (*weights)[static_cast<std::size_t>(e)] : 1.0; }
  template <class Vec>
  double gather(const Vec& u, int k) const {
    const int i = k / comps(), c = k % comps();
    double s = 0.0;
    for (int e = first(i); e < last(i); ++e)
      for (int d = 0; d < dim; ++d) {
        const int f = (*dofs)[static_cast<std::size_t>(dim * e + d)];
        if (f >= 0) s += weight(e) * dirs(d, c) * u[f];
      }
    return s;
  }
  template <class Vec>
  void scatterAdd(Vec& u, int k, double f) const {
    const int i = k / comps(), c = k % comps();
    for (int e = first(i); e < last(i); ++e)
      for (int d = 0; d < dim; ++d) {
        const int fd = (*dofs)[static_cast<std::size_t>(dim * e + d)];
        if (fd >= 0) u[fd] += weight(e) * dirs(d, c) * f;
      }
  }
};

class TissueIntegrator {
 public:
  virtual ~TissueIntegrator() = default;
  virtual Backend kind() const = 0;
  virtual void prepare(const NewmarkCoefficients& c) = 0;
  virtual const Eigen::MatrixXd& S() const = 0;
  virtual void predict(Eigen::VectorXd& u0P) = 0;
  virtual void commit(const Eigen::VectorXd& f) = 0;
  virtual void fullDisplacement(Eigen::VectorXd& u) const = 0;  // free DOFs
  virtual void fullVelocity(Eigen::VectorXd& v) const = 0;      // free DOFs
  // Copies the displacement's state into `state`: O(its size), no allocation once sized.
  virtual void saveDisplacement(DisplacementState& state) const = 0;
  // u on the free DOFs from a saved state. Reads only the basis and path placement, which
  // stepping never changes, so it may run in another thread while the integrator steps.
  virtual void displacementOf(const DisplacementState& state, Eigen::VectorXd& u) const = 0;
  virtual void setState(const Eigen::VectorXd& u, const Eigen::VectorXd& v, const Eigen::VectorXd& a) = 0;
  virtual double freeDisplacement(int k) const = 0;  // one free DOF of u
  // Path point i's entries changed in the map (it was moved before it took any load): its
  // rows and columns of the path flexibility, from the existing factorisation or basis.
  virtual void movePathPoint(int i) = 0;
};

std::unique_ptr<TissueIntegrator> makeDirectIntegrator(const Eigen::SparseMatrix<double>& K,
                                                       const Eigen::SparseMatrix<double>& M, double alpha,
                                                       double beta, PathMap map, materials::Prony prony);
std::unique_ptr<TissueIntegrator> makeModalIntegrator(const Eigen::SparseMatrix<double>& K,
                                                      const Eigen::SparseMatrix<double>& M, double alpha,
                                                      double beta, PathMap map, materials::Prony prony);
// Keeps the modes below `cutoff` (rad/s), at most max_modes.
std::unique_ptr<TissueIntegrator> makeReducedIntegrator(const Eigen::SparseMatrix<double>& K,
                                                        const Eigen::SparseMatrix<double>& M, double alpha,
                                                        double beta, PathMap map, double cutoff, int max_modes,
                                                        materials::Prony prony);

}  // namespace needlesim::realtime
