#include "needlesim/engines/realtime/dof_map.hpp"

#include "needlesim/core/progress.hpp"

namespace needlesim::realtime {

DofMap makeDofMap(int total_dofs, const std::vector<bool>& held) {
  DofMap m;
  m.free_of_dof.assign(static_cast<std::size_t>(total_dofs), -1);
  for (int d = 0; d < total_dofs; ++d)
    if (!held[static_cast<std::size_t>(d)]) {
      m.free_of_dof[static_cast<std::size_t>(d)] = m.freeCount();
      m.dof_of_free.push_back(d);
    }
  return m;
}

Eigen::SparseMatrix<double> sparseFrom(int n, const std::vector<Eigen::Triplet<double>>& t) {
  Eigen::SparseMatrix<double> A(n, n);
  const BlockingCall call("realtime tissue: sparse matrix of the mesh");
  A.setFromTriplets(t.begin(), t.end());
  return A;
}

Eigen::SparseMatrix<double> restrictToFree(const Eigen::SparseMatrix<double>& A, const DofMap& map) {
  std::vector<Eigen::Triplet<double>> t;
  t.reserve(static_cast<std::size_t>(A.nonZeros()));
  for (int c = 0; c < A.outerSize(); ++c)
    for (Eigen::SparseMatrix<double>::InnerIterator it(A, c); it; ++it) {
      const int r = map.free_of_dof[static_cast<std::size_t>(it.row())];
      const int cc = map.free_of_dof[static_cast<std::size_t>(it.col())];
      if (r >= 0 && cc >= 0) t.emplace_back(r, cc, it.value());
    }
  Eigen::SparseMatrix<double> R(map.freeCount(), map.freeCount());
  const BlockingCall call("realtime tissue: the free degrees of freedom");
  R.setFromTriplets(t.begin(), t.end());
  return R;
}

}  // namespace needlesim::realtime
