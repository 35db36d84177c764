// The support of a material point (base node, shape function weights and
// derivatives along x, y, z) on four vector lanes, lane = axis, for the
// particle passes of mpm_solver.cpp: one set of vector operations for the three
// axes instead of three scalar ones (grid::weights), and the per-axis values
// the tensor-product loops need are one lane broadcast each. The same
// operations in the same order as grid::weights, so the same bits (the
// penalty contact keeps grid::stencil). Included by mpm_solver.cpp only; the
// helpers are always inlined (they pass vectors by value, see ld() there).
#pragma once

#include <cstddef>

#include "needlesim/materials/stress_lanes.hpp"  // materials::lanes::A4, I4

namespace needlesim::mpm::lanes {

using materials::lanes::A4;
using materials::lanes::I4;

typedef int I4x32 __attribute__((vector_size(16)));

// w[a], d[a]: weight and derivative of the a-th node along each axis (lanes
// x, y, z; lane 3 unused); b*: base node indices.
template <int S>
struct Support {
  A4 w[S], d[S];
  std::size_t bx, by, bz;
};

// x: the position, read as four doubles (the fourth, lane 3, is ignored; in
// MpmSolver::Point it is the first velocity component). o: grid origin (lane 3
// unused). Points lie inside the grid, so truncation is the floor.
template <int S>
[[gnu::always_inline]] inline Support<S> support(const double* x, A4 o, double invh) {
  Support<S> s;
  const A4 xi = (*reinterpret_cast<const A4*>(x) - o) * invh;
  I4x32 bi;
  A4 f;
  if constexpr (S == 2) {  // linear hat
    bi = __builtin_convertvector(xi, I4x32);
    f = xi - __builtin_convertvector(bi, A4);
    s.w[0] = 1.0 - f;
    s.w[1] = f;
    s.d[0] = A4{} - invh;
    s.d[1] = A4{} + invh;
  } else {  // quadratic B-spline
    bi = __builtin_convertvector(xi - 0.5, I4x32);
    f = xi - __builtin_convertvector(bi, A4);  // in [0.5, 1.5)
    const A4 a0 = 1.5 - f, a1 = f - 1.0, a2 = f - 0.5;
    s.w[0] = 0.5 * a0 * a0;
    s.w[1] = 0.75 - a1 * a1;
    s.w[2] = 0.5 * a2 * a2;
    s.d[0] = -a0 * invh;
    s.d[1] = -2.0 * a1 * invh;
    s.d[2] = a2 * invh;
  }
  s.bx = static_cast<std::size_t>(bi[0]);
  s.by = static_cast<std::size_t>(bi[1]);
  s.bz = static_cast<std::size_t>(bi[2]);
  return s;
}

// Lane l of v in all four lanes (one vpermpd in the AVX2 clone).
template <int l>
[[gnu::always_inline]] inline A4 lane(A4 v) {
  return __builtin_shuffle(v, I4{l, l, l, l});
}

// The support as the tensor-product loops use it: each weight and derivative
// broadcast to four lanes, so w_i w_j, the gradient products and w_k a are
// lane products (the same rounding as the scalar products, without a scalar
// multiply and a broadcast for each).
template <int S>
struct Stencil4 {
  A4 wx[S], wy[S], wz[S], dx[S], dy[S], dz[S];
  std::size_t bx, by, bz;
};

template <int S>
[[gnu::always_inline]] inline Stencil4<S> stencil4(const double* x, A4 o, double invh) {
  const Support<S> s = support<S>(x, o, invh);
  Stencil4<S> b;
  for (int a = 0; a < S; ++a) {
    b.wx[a] = lane<0>(s.w[a]);
    b.wy[a] = lane<1>(s.w[a]);
    b.wz[a] = lane<2>(s.w[a]);
    b.dx[a] = lane<0>(s.d[a]);
    b.dy[a] = lane<1>(s.d[a]);
    b.dz[a] = lane<2>(s.d[a]);
  }
  b.bx = s.bx;
  b.by = s.by;
  b.bz = s.bz;
  return b;
}

}  // namespace needlesim::mpm::lanes
