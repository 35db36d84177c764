#pragma once
// The Newmark back-ends of the realtime2d tissue (tissue.hpp): direct sparse LDLT, modal
// (all modes) and reduced (lowest modes plus residual flexibility), behind one interface.
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <array>
#include <memory>
#include <vector>

#include "needlesim/engines/realtime2d/tissue.hpp"
#include "needlesim/materials/viscoelastic.hpp"

namespace needlesim::realtime2d {

struct PathMap {  // the path loads' placement on the free DOFs
  const std::vector<std::array<int, 2>>* pdof;
  Eigen::Vector2d t, n;
  // Direction (x, y) of path load k (k = 2 i + 0: axial t, + 1: lateral n).
  const Eigen::Vector2d& dir(int k) const { return (k % 2 == 0) ? t : n; }
  template <class Vec>
  double gather(const Vec& u, int k) const {
    const auto& d = (*pdof)[static_cast<std::size_t>(k / 2)];
    const auto& e = dir(k);
    double s = 0.0;
    if (d[0] >= 0) s += e.x() * u[d[0]];
    if (d[1] >= 0) s += e.y() * u[d[1]];
    return s;
  }
  template <class Vec>
  void scatterAdd(Vec& u, int k, double f) const {
    const auto& d = (*pdof)[static_cast<std::size_t>(k / 2)];
    const auto& e = dir(k);
    if (d[0] >= 0) u[d[0]] += e.x() * f;
    if (d[1] >= 0) u[d[1]] += e.y() * f;
  }
  int size() const { return 2 * static_cast<int>(pdof->size()); }
};

class TissueIntegrator {
 public:
  virtual ~TissueIntegrator() = default;
  virtual Backend kind() const = 0;
  virtual void prepare(const NewmarkCoefficients& c) = 0;
  virtual const Eigen::MatrixXd& S() const = 0;
  virtual void predict(Eigen::VectorXd& u0P) = 0;
  virtual void commit(const Eigen::VectorXd& f) = 0;
  virtual void fullState(Eigen::VectorXd& u, Eigen::VectorXd& v) const = 0;  // free DOFs
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

}  // namespace needlesim::realtime2d
