// Grid record layout and 1D shape functions shared by the MPM kernels
// (mpm_solver.cpp) and the two-body penalty contact (penalty_contact.cpp).
// Seed 000 eqs 1-4 (linear hat); quadratic B-spline for section 5.2's noise.
#pragma once

#include <cstddef>
#include <new>
#include <vector>

namespace needlesim::mpm::grid {

// Offsets in a grid record (MpmSolver::Buf::rec, 8 doubles): mass, momentum
// (3), force (3), pad.
constexpr std::size_t kM = 0, kP = 1, kF = 4;
// Two bodies, offsets in a gradient record (MpmSolver::Buf::grad, 8 doubles):
// mass gradient (3), pad (5).
constexpr std::size_t kG = 0;

// Allocator on cache-line boundaries: a 64-byte grid record then never
// straddles two lines, so its 32-byte vector loads and stores stay within one
// line and the store of one point's scatter forwards to the next point's load.
template <class T>
struct LineAllocator {
  using value_type = T;
  LineAllocator() = default;
  template <class U>
  LineAllocator(const LineAllocator<U>&) {}
  T* allocate(std::size_t n) { return static_cast<T*>(::operator new(n * sizeof(T), std::align_val_t{64})); }
  void deallocate(T* p, std::size_t) { ::operator delete(p, std::align_val_t{64}); }
  template <class U>
  bool operator==(const LineAllocator<U>&) const { return true; }
};
template <class T>
using LineVector = std::vector<T, LineAllocator<T>>;

// Cell of a coordinate xi >= 0 (in cells from the grid origin; points lie
// inside the grid): through int, one instruction (double to size_t is a
// branchy sequence on x86-64 without AVX-512).
inline std::size_t cellOf(double xi) { return static_cast<std::size_t>(static_cast<int>(xi)); }

// The cell (i, j, k) holding a point at (xi, yi, zi) cells from the grid
// origin, as its (i, j) row i n1 + j and k (the bit rows of
// NearBodies::mark, the penalty contact's cell lists).
struct Cell {
  std::size_t row, k;
};
inline Cell cellAt(double xi, double yi, double zi, std::size_t n1) { return {cellOf(xi) * n1 + cellOf(yi), cellOf(zi)}; }

// Shape functions along one axis: base node index, weights and derivatives.
// xi >= 0 inside the grid (finalize and g2pFinal check it), so truncation is
// the floor (std::floor is a library call without SSE4.1).
template <int S>
inline int weights(double xi, double invh, double* w, double* dw) {
  if constexpr (S == 2) {  // linear hat
    const double b = static_cast<double>(static_cast<int>(xi));
    const double f = xi - b;
    w[0] = 1.0 - f;
    w[1] = f;
    dw[0] = -invh;
    dw[1] = invh;
    return static_cast<int>(b);
  } else {  // quadratic B-spline, support 3 nodes
    const double b = static_cast<double>(static_cast<int>(xi - 0.5));
    const double f = xi - b;  // in [0.5, 1.5)
    const double a0 = 1.5 - f, a1 = f - 1.0, a2 = f - 0.5;
    w[0] = 0.5 * a0 * a0;
    w[1] = 0.75 - a1 * a1;
    w[2] = 0.5 * a2 * a2;
    dw[0] = -a0 * invh;
    dw[1] = -2.0 * a1 * invh;
    dw[2] = a2 * invh;
    return static_cast<int>(b);
  }
}

// The support of a point: weights and derivatives along each axis and the
// base node (the penalty contact; the particle passes of mpm_solver.cpp use
// the same operations on vector lanes, support_lanes.hpp).
template <int S>
struct Stencil {
  double wx[S], wy[S], wz[S], dx[S], dy[S], dz[S];
  int bx, by, bz;
};

template <int S>
[[gnu::always_inline]] inline Stencil<S> stencil(const double* x, double ox, double oy, double oz, double invh) {
  Stencil<S> s;
  s.bx = weights<S>((x[0] - ox) * invh, invh, s.wx, s.dx);
  s.by = weights<S>((x[1] - oy) * invh, invh, s.wy, s.dy);
  s.bz = weights<S>((x[2] - oz) * invh, invh, s.wz, s.dz);
  return s;
}

}  // namespace needlesim::mpm::grid
