#pragma once
// Symmetric positive definite banded solver (Cholesky, LL^T) with a fixed
// half-bandwidth. Storage is reserved once; factor/solve never allocate.
#include <algorithm>
#include <cassert>
#include <cmath>
#include <stdexcept>
#include <vector>

namespace needlesim::needle {

template <int HB>  // half-bandwidth: a(i, j) = 0 for |i - j| > HB
class BandedSPD {
 public:
  void reserve(int n) {
    if (static_cast<int>(a_.size()) < n * (HB + 1)) a_.resize(static_cast<size_t>(n) * (HB + 1));
  }
  // Resets to an n x n zero matrix (n <= reserved size unless reserve grows it).
  void reset(int n) {
    reserve(n);
    n_ = n;
    std::fill(a_.begin(), a_.begin() + static_cast<long>(n) * (HB + 1), 0.0);
  }
  int size() const { return n_; }
  // Lower band entry (i >= j, i - j <= HB).
  double& at(int i, int j) {
    assert(i >= j && i - j <= HB && i < n_);
    return a_[static_cast<size_t>(i) * (HB + 1) + (i - j)];
  }
  // Adds a symmetric element block: rows/cols given by dofs (negative = constrained, skipped).
  template <class Mat, int N>
  void addBlock(const Mat& k, const int (&dofs)[N]) {
    for (int r = 0; r < N; ++r) {
      if (dofs[r] < 0) continue;
      for (int c = 0; c < N; ++c) {
        if (dofs[c] < 0 || dofs[c] > dofs[r]) continue;
        at(dofs[r], dofs[c]) += k(r, c);
      }
    }
  }
  // In-place Cholesky. Throws if the matrix is not positive definite.
  void factor() { factorFrom(0); }
  // Row-oriented (left-looking) Cholesky of rows first..n-1, assuming rows < first
  // already hold the factor: appending to the end of a banded system costs O(HB^2) per
  // new row instead of a full refactorisation. Rows >= first must hold matrix entries.
  void factorFrom(int first) {
    for (int i = first; i < n_; ++i) {
      const int k0 = i - HB > 0 ? i - HB : 0;
      for (int j = k0; j < i; ++j) {
        double s = at(i, j);
        for (int k = k0; k < j; ++k) s -= at(i, k) * at(j, k);
        at(i, j) = s / at(j, j);
      }
      double d = at(i, i);
      for (int k = k0; k < i; ++k) d -= at(i, k) * at(i, k);
      if (!(d > 0)) throw std::runtime_error("banded solver: matrix not positive definite");
      at(i, i) = std::sqrt(d);
    }
  }
  // Zeroes rows first..n-1 (lower band), keeping earlier rows, and sets the size to n.
  void truncateRows(int first, int n) {
    reserve(n);
    n_ = n;
    std::fill(a_.begin() + static_cast<long>(first) * (HB + 1), a_.begin() + static_cast<long>(n) * (HB + 1), 0.0);
  }
  // Adds only the entries of rows >= first_row.
  template <class Mat, int N>
  void addBlockRows(const Mat& k, const int (&dofs)[N], int first_row) {
    for (int r = 0; r < N; ++r) {
      if (dofs[r] < first_row) continue;
      for (int c = 0; c < N; ++c) {
        if (dofs[c] < 0 || dofs[c] > dofs[r]) continue;
        at(dofs[r], dofs[c]) += k(r, c);
      }
    }
  }
  // Forward substitution L y = b for rows first..n-1 (rows < first already hold y).
  void forwardFrom(double* b, int first) {
    for (int i = first; i < n_; ++i) {
      double s = b[i];
      const int k0 = i - HB > 0 ? i - HB : 0;
      for (int k = k0; k < i; ++k) s -= at(i, k) * b[k];
      b[i] = s / at(i, i);
    }
  }
  // Back substitution L^T x = y in place.
  void backward(double* b) {
    for (int i = n_ - 1; i >= 0; --i) {
      double s = b[i];
      const int kend = i + HB < n_ - 1 ? i + HB : n_ - 1;
      for (int k = i + 1; k <= kend; ++k) s -= at(k, i) * b[k];
      b[i] = s / at(i, i);
    }
  }
  // x[n-2] of L^T x = y without touching b (needs n >= 2).
  double backLastTwo(const double* b) {
    const int i = n_ - 1;
    const double xl = b[i] / at(i, i);
    return (b[i - 1] - at(i, i - 1) * xl) / at(i - 1, i - 1);
  }
  // Solves in place with the factor (b has size() entries).
  void solve(double* b) {
    for (int i = 0; i < n_; ++i) {
      double s = b[i];
      const int k0 = i - HB > 0 ? i - HB : 0;
      for (int k = k0; k < i; ++k) s -= at(i, k) * b[k];
      b[i] = s / at(i, i);
    }
    for (int i = n_ - 1; i >= 0; --i) {
      double s = b[i];
      const int kend = i + HB < n_ - 1 ? i + HB : n_ - 1;
      for (int k = i + 1; k <= kend; ++k) s -= at(k, i) * b[k];
      b[i] = s / at(i, i);
    }
  }

 private:
  std::vector<double> a_;
  int n_ = 0;
};

}  // namespace needlesim::needle
