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

// The path loads' placement on the free DOFs: path node i has `dim` spatial DOFs
// (dofs[dim i + d], -1 when held) and comps() load components, component c acting along
// dirs.col(c) (axial first, then the lateral directions). Path load k = comps() i + c.
struct PathMap {
  const std::vector<int>* dofs = nullptr;
  int dim = 2;
  Eigen::MatrixXd dirs;  // dim x comps
  int comps() const { return static_cast<int>(dirs.cols()); }
  int nodes() const { return static_cast<int>(dofs->size()) / dim; }
  int size() const { return comps() * nodes(); }
  template <class Vec>
  double gather(const Vec& u, int k) const {
    const int i = k / comps(), c = k % comps();
    double s = 0.0;
    for (int d = 0; d < dim; ++d) {
      const int f = (*dofs)[static_cast<std::size_t>(dim * i + d)];
      if (f >= 0) s += dirs(d, c) * u[f];
    }
    return s;
  }
  template <class Vec>
  void scatterAdd(Vec& u, int k, double f) const {
    const int i = k / comps(), c = k % comps();
    for (int d = 0; d < dim; ++d) {
      const int fd = (*dofs)[static_cast<std::size_t>(dim * i + d)];
      if (fd >= 0) u[fd] += dirs(d, c) * f;
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
