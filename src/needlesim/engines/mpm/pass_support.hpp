#pragma once
// What the MPM particle and grid passes share (particle_to_grid.cpp,
// grid_update.cpp, grid_to_particle.cpp, needle_cut.cpp): four-lane loads and
// adds of grid records, the kernels' function multiversioning, software
// prefetch of particle records, the OpenMP thread of a pass.
#include <cstddef>
#include <cstdint>
#include <limits>

#include "needlesim/engines/mpm/grid_kernels.hpp"
#include "needlesim/engines/mpm/support_lanes.hpp"

#ifdef _OPENMP
#include <omp.h>
#endif

// Function multiversioning of the particle-grid kernels: a baseline x86-64
// clone and an x86-64-v3 (AVX2, FMA) clone chosen at load time, so the default
// build runs on any x86-64 (no -march=native). Off with NEEDLESIM_MPM_NO_CLONES.
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && !defined(NEEDLESIM_MPM_NO_CLONES)
#define MPM_CLONES __attribute__((target_clones("arch=x86-64-v3", "default")))
#else
#define MPM_CLONES
#endif

namespace needlesim::mpm::pass {

constexpr double kInf = std::numeric_limits<double>::infinity();
// Four lanes of a grid record as a GCC vector: two SSE2 operations in the
// baseline x86-64 build, one AVX2/FMA operation in the x86-64-v3 clones of the
// hot kernels (NEEDLESIM_MPM_CLONES). Unaligned, may alias double.
using lanes::A4;  // support_lanes.hpp (materials/stress_lanes.hpp)
// Always inlined, also at -O0: a call would pass A4 by the baseline ABI
// (memory) from an AVX2 clone that expects it in a register.
[[gnu::always_inline]] inline A4 ld(const double* p) { return *reinterpret_cast<const A4*>(p); }
[[gnu::always_inline]] inline void add(double* p, A4 v) { *reinterpret_cast<A4*>(p) += v; }
// 0.0 that the compiler cannot see through: lanes packed with it compile to
// unpack/insert instructions instead of the VEX "vmovq xmm, xmm" that
// valgrind 3.19 cannot decode (callgrind counts of docs/performance.md).
inline double opaqueZero() {
  double z = 0.0;
#if defined(__GNUC__) && defined(__x86_64__)
  asm("" : "+x"(z));
#endif
  return z;
}
// Grid record offsets (grid_kernels.hpp).
using grid::kM, grid::kP, grid::kF;


// Software prefetch of the record of a point a few visits ahead, the cache
// lines of mask Lines (bit l: line l of the 256-byte Point): perf showed the
// particle passes stalled on the first touch of a record's lines (the two-body
// scatter 32 % of its time on the stress line), which the hardware prefetchers
// do not fetch early enough for records visited in block order.
constexpr std::size_t kPrefetchAhead = 6;
template <unsigned Lines>
[[gnu::always_inline]] inline void prefetchRecord(const void* rec) {
  const char* c = static_cast<const char*>(rec);
  if constexpr ((Lines & 1u) != 0) __builtin_prefetch(c, 1, 3);
  if constexpr ((Lines & 2u) != 0) __builtin_prefetch(c + 64, 1, 3);
  if constexpr ((Lines & 4u) != 0) __builtin_prefetch(c + 128, 1, 3);
  if constexpr ((Lines & 8u) != 0) __builtin_prefetch(c + 192, 1, 3);
}

inline int threadId() {
#ifdef _OPENMP
  return omp_get_thread_num();
#else
  return 0;
#endif
}

inline int teamSize() {
#ifdef _OPENMP
  return omp_get_num_threads();
#else
  return 1;
#endif
}


}  // namespace needlesim::mpm::pass
