#pragma once
// Numbering of the free DOFs of a real-time tissue after removing the held ones.
#include <Eigen/SparseCore>
#include <vector>

namespace needlesim::realtime {

struct DofMap {
  std::vector<int> free_of_dof;  // -1 for a held DOF
  std::vector<int> dof_of_free;
  int freeCount() const { return static_cast<int>(dof_of_free.size()); }
};
DofMap makeDofMap(int total_dofs, const std::vector<bool>& held);
// An n x n sparse matrix from (row, column, value) triplets (duplicates summed).
Eigen::SparseMatrix<double> sparseFrom(int n, const std::vector<Eigen::Triplet<double>>& t);
// Rows and columns of the free DOFs only.
Eigen::SparseMatrix<double> restrictToFree(const Eigen::SparseMatrix<double>& A, const DofMap& map);

}  // namespace needlesim::realtime
