#pragma once
// The sparse Cholesky factorisation of the real-time tissues' set-up (stiffness, mass): CHOLMOD's
// supernodal LL^T (Debian libsuitesparse-dev) through Eigen's CholmodSupport. Silent: a matrix
// that is not positive definite shows in info(), which every caller checks, not on stderr.
#include <Eigen/CholmodSupport>
#include <Eigen/SparseCore>

namespace needlesim::realtime {

class SparseCholesky : public Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>> {
 public:
  SparseCholesky() { cholmod().print = 0; }
};

}  // namespace needlesim::realtime
