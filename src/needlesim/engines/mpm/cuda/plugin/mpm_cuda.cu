// The CUDA MPM plugin (libneedlesim_mpm_cuda.so): device memory, point
// sorting, launches and reductions around the physics of
// mpm_device_kernels.hpp, behind the C interface of mpm_device_abi.h. The
// state stays on the device between steps; one small copy of the step's
// totals comes back per step, the particles only on download.
// Kernels: NAIVE (one thread per point in storage order, global atomics) and
// SORTED (points sorted by base cell with CUB's radix sort every 8 steps; in
// P2G and the MUSL remap each run of sorted points in one cell sums its
// contributions with warp shuffles and its first lane adds them with global
// atomics: the warp-level reduction of Gao et al. 2018). Variants for
// measurement (environment): NEEDLESIM_MPM_CUDA_TILE=1 adds into a
// shared-memory tile of the nodes of a block first (the block-local P2G of
// Claymore, Wang et al. 2020; slower on an H200 with fp64), SPREAD=1 runs the
// blocks in a spread order, MINBLOCKS=8 halves the registers, WARP=0 drops the
// warp sums, SORT_EVERY=N, PROFILE=1 prints per-phase device times.
#include <cub/cub.cuh>
#include <cuda_runtime.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "needlesim/engines/mpm/cuda/mpm_device_kernels.hpp"

using namespace nsmpm;

namespace {

constexpr int kThreads = 256;
constexpr int kTileThreads = 128;  // points per block of the tiled P2G
constexpr int kTileCells = 88;     // cell-index span of a block that fits its tile
constexpr int kTileRow = kTileCells + 3;
constexpr int kTileEntries = 9 * kTileRow * 7;  // (i, j) x k span x record entries 0-6: 45.9 kB
constexpr int kPointDoubles = 24;               // x 3, v 3, mass, vol0, vol, F 9, sig 6

// Device totals of one step, copied back once.
struct Totals {
  ForceSums sums;
  double kinetic, internal;
  unsigned long long maxSpeedBits;
  int failure;
  unsigned long long failedSlot;
};

struct Run {
  NsMpmConfig cfg{};
  size_t n = 0, nodes = 0;
  cudaStream_t stream = nullptr;
  double *pdata = nullptr, *pscratch = nullptr, *vg = nullptr;
  uint8_t *mat = nullptr, *matScratch = nullptr;
  uint32_t *orig = nullptr, *origScratch = nullptr;
  uint32_t *keys = nullptr, *keysOut = nullptr, *slots = nullptr, *perm = nullptr;
  void* cubTemp = nullptr;
  size_t cubBytes = 0;
  int keyBits = 32;
  double *rec = nullptr, *vel = nullptr, *rnormal = nullptr, *dash = nullptr;
  uint64_t* gmin = nullptr;
  uint8_t *active = nullptr, *fix = nullptr;
  Totals* totals = nullptr;
  Totals* hostTotals = nullptr;
  long long steps = 0;
  int sortEvery = 8;
  int warpReduce = 1;  // NEEDLESIM_MPM_CUDA_WARP=0: the sorted kernel without the warp-level sums
  int tile = 0;        // NEEDLESIM_MPM_CUDA_TILE=1: the sorted kernel adds into a shared-memory tile first
  int spread = 0;      // NEEDLESIM_MPM_CUDA_SPREAD=1: blocks of the warp scatter in a spread order
  int minBlocks = 4;   // NEEDLESIM_MPM_CUDA_MINBLOCKS=8: the warp scatter with half the registers
  std::vector<double> staging;
  std::vector<uint32_t> hostOrig;
  // NEEDLESIM_MPM_CUDA_PROFILE: per-phase device times, summed and printed at destroy.
  bool profile = false;
  cudaEvent_t marks[8] = {};
  double phaseMs[7] = {};
  long long profiled = 0;
};

// Phases between the profile marks.
const char* const kPhases[7] = {"sort", "clear", "p2g", "grid", "remap scatter", "remap update", "g2p+stress"};

void mark(Run& r, int i) {
  if (r.profile) cudaEventRecord(r.marks[i], r.stream);
}

// After a step's sync: the phase times of this step into the sums.
void collectPhases(Run& r) {
  if (!r.profile) return;
  for (int i = 0; i < 7; ++i) {
    float ms = 0.0f;
    if (cudaEventElapsedTime(&ms, r.marks[i], r.marks[i + 1]) == cudaSuccess) r.phaseMs[i] += ms;
  }
  ++r.profiled;
}

void printPhases(const Run& r) {
  if (!r.profile || r.profiled == 0) return;
  std::fprintf(stderr, "mpm cuda profile: %zu points, %lld steps, mean per step:", r.n, r.profiled);
  for (int i = 0; i < 7; ++i) std::fprintf(stderr, " %s %.1f us;", kPhases[i], 1e3 * r.phaseMs[i] / r.profiled);
  std::fprintf(stderr, "\n");
}

unsigned blocks(size_t count, int threads) { return static_cast<unsigned>((count + threads - 1) / threads); }

Points pointsOf(const Run& r) {
  const size_t n = r.n;
  double* b = r.pdata;
  return Points{n, b, b + 3 * n, b + 6 * n, b + 7 * n, b + 8 * n, b + 9 * n, b + 18 * n, r.vg, r.mat};
}

Grid gridOf(const Run& r) {
  const NsMpmConfig& c = r.cfg;
  return Grid{c.nodes[0], c.nodes[1], c.nodes[2], r.nodes, c.h, 1.0 / c.h, c.origin[0], c.origin[1], c.origin[2],
              r.rec, r.vel, r.gmin, r.active, r.rnormal, r.fix, r.dash};
}

// ---------------------------------------------------------------- kernels

__global__ void fillKeys(uint64_t* a, size_t count, uint64_t v) {
  const size_t i = blockIdx.x * static_cast<size_t>(blockDim.x) + threadIdx.x;
  if (i < count) a[i] = v;
}

template <int S>
__global__ void p2gNaive(Grid g, Points pt, Params P) {
  const size_t p = blockIdx.x * static_cast<size_t>(blockDim.x) + threadIdx.x;
  if (p < pt.n) p2gPoint<S>(g, pt, P, p);
}

// Adds into the block's shared tile: node (bx + i, by + j, bz + k) of a point
// whose base cell index is c = c0 + local sits at row 3 i + j, column local + k.
struct TileSink {
  double* tile;
  long long local;
  int bx, by, bz;
  NSMPM_HD double* node(int ai, int aj, int ak) const {
    return tile + ((static_cast<long long>((ai - bx) * 3 + (aj - by)) * kTileRow + local + (ak - bz)) * 7);
  }
  NSMPM_HD void add(double* r, int c, double v) const { addTo(r + c, v); }
};

// Warp-level pre-reduction (Gao et al. 2018, GPU optimization of MPM): sorted
// points with the same base cell sit in neighbouring lanes and add into the
// same nodes, so each run of equal cells sums its contributions by shuffles
// and only its first lane adds. `mask`: the lanes taking part (the warp's
// valid points, contiguous from lane 0, from a ballot of the whole warp);
// key: the lane's base cell.
struct WarpRun {
  unsigned mask;
  int lane, end, width;  // end: last lane of this lane's run; width: longest run in the warp
  bool head;
  __device__ static WarpRun of(unsigned key, unsigned mask) {
    WarpRun w;
    w.mask = mask;
    w.lane = static_cast<int>(threadIdx.x % 32);
    const unsigned prev = __shfl_up_sync(w.mask, key, 1);
    w.head = w.lane == 0 || prev != key;
    const unsigned heads = __ballot_sync(w.mask, w.head);
    const unsigned above = heads & ~((2u << w.lane) - 1u);
    const int last = 31 - __clz(w.mask);
    w.end = above ? __ffs(above) - 2 : last;
    const unsigned run = w.head ? static_cast<unsigned>(w.end - w.lane + 1) : 1u;
    w.width = static_cast<int>(__reduce_max_sync(w.mask, run));
    return w;
  }
  __device__ double sum(double v) const {
    for (int d = 1; d < width; d <<= 1) {
      const double o = __shfl_down_sync(mask, v, d);
      if (lane + d <= end) v += o;
    }
    return v;
  }
};

template <class Inner>
struct WarpSink {
  Inner in;
  WarpRun w;
  __device__ double* node(int i, int j, int k) const { return in.node(i, j, k); }
  __device__ void add(double* r, int c, double v) const {
    const double total = w.sum(v);
    if (w.head) in.add(r, c, total);
  }
};

// What a tiled scatter adds: P2G (mass, momentum, force) or the MUSL remap (momentum).
enum class Scatter { P2G, Remap };

template <int S, Scatter What, class Sink>
__device__ void scatterInto(const Grid& g, const Points& pt, const Params& P, size_t p, const Stencil<S>& st,
                            const Sink& sink) {
  if (What == Scatter::P2G) scatterPoint<S>(pt, p, st, sink);
  else g2pRemapPoint<S>(g, pt, P, p, st, sink);
}

// Tiled scatter over sorted points: the block's base cells span at most
// kTileCells in index, so its nodes fit a 9 x kTileRow tile in shared memory;
// the block adds there, then each non-zero entry once into the global grid.
// A block whose points spread wider adds globally.
template <int S, Scatter What>
__global__ void __launch_bounds__(kTileThreads) scatterTiled(Grid g, Points pt, Params P) {
  __shared__ double tile[kTileEntries];
  __shared__ unsigned long long cmin;
  const size_t p = blockIdx.x * static_cast<size_t>(blockDim.x) + threadIdx.x;
  const bool valid = p < pt.n;
  const size_t n = pt.n;
  Stencil<S> st{};
  double x[3] = {0, 0, 0};
  unsigned long long c = 0;
  if (valid) {
    x[0] = pt.x[p];
    x[1] = pt.x[n + p];
    x[2] = pt.x[2 * n + p];
    st = stencilAt<S>(g, x[0], x[1], x[2]);
    c = nodeIndex(g, st.bx, st.by, st.bz);
  }
  if (threadIdx.x == 0) cmin = ~0ull;
  __syncthreads();
  if (valid) atomicMin(&cmin, c);
  __syncthreads();
  const unsigned long long c0 = cmin;
  const bool wide = __syncthreads_or(!P.tile || (valid && c - c0 > static_cast<unsigned long long>(kTileCells - S + 1)));
  const unsigned validLanes = __ballot_sync(0xffffffffu, valid);
  if (wide) {
    if (valid) {
      const GlobalSink sink{&g};
      if (P.warpReduce) scatterInto<S, What>(g, pt, P, p, st, WarpSink<GlobalSink>{sink, WarpRun::of(static_cast<unsigned>(c), validLanes)});
      else scatterInto<S, What>(g, pt, P, p, st, sink);
    }
  } else {
    for (int e = threadIdx.x; e < kTileEntries; e += blockDim.x) tile[e] = 0.0;
    __syncthreads();
    if (valid) {
      const TileSink sink{tile, static_cast<long long>(c - c0), st.bx, st.by, st.bz};
      if (P.warpReduce) scatterInto<S, What>(g, pt, P, p, st, WarpSink<TileSink>{sink, WarpRun::of(static_cast<unsigned>(c), validLanes)});
      else scatterInto<S, What>(g, pt, P, p, st, sink);
    }
    __syncthreads();
    const size_t nz = static_cast<size_t>(g.nz), nyz = static_cast<size_t>(g.ny) * nz;
    for (int e = threadIdx.x; e < kTileEntries; e += blockDim.x) {
      const double v = tile[e];
      if (v == 0.0) continue;
      const int comp = e % 7, slot = e / 7, ij = slot / kTileRow, col = slot % kTileRow;
      const size_t node = c0 + static_cast<size_t>(col) + static_cast<size_t>(ij / 3) * nyz + static_cast<size_t>(ij % 3) * nz;
      if (node < g.nodes) atomicAdd(g.rec + 8 * node + comp, v);
    }
  }
  if (What == Scatter::P2G && valid && P.cfg.nRigids > 0) gapMinima<S>(g, P, x, st);
}

// Block b of n in an order that spreads the blocks running at one time over
// the sorted points (b times a prime, mod n): fewer of their atomics meet at
// one node (NEEDLESIM_MPM_CUDA_SPREAD=1).
__device__ unsigned spreadBlock(unsigned b, unsigned n) {
  const unsigned long long s = n % 7919u != 0 ? 7919u : 7907u;
  return static_cast<unsigned>((static_cast<unsigned long long>(b) * s) % n);
}

// The sorted kernel's default scatter: warp-level sums of the runs of points in
// one cell, then global atomics (faster than the shared-memory tile on an H200:
// docs/performance.md). MinBlocks: the register budget (launch bounds).
template <int S, Scatter What, int MinBlocks>
__global__ void __launch_bounds__(kTileThreads, MinBlocks) scatterWarp(Grid g, Points pt, Params P) {
  const unsigned b = P.spread ? spreadBlock(blockIdx.x, gridDim.x) : blockIdx.x;
  const size_t p = b * static_cast<size_t>(blockDim.x) + threadIdx.x;
  const bool valid = p < pt.n;
  const unsigned validLanes = __ballot_sync(0xffffffffu, valid);
  if (!valid) return;
  const size_t n = pt.n;
  const double x[3] = {pt.x[p], pt.x[n + p], pt.x[2 * n + p]};
  const Stencil<S> st = stencilAt<S>(g, x[0], x[1], x[2]);
  const unsigned c = static_cast<unsigned>(nodeIndex(g, st.bx, st.by, st.bz));
  const GlobalSink sink{&g};
  if (P.warpReduce) scatterInto<S, What>(g, pt, P, p, st, WarpSink<GlobalSink>{sink, WarpRun::of(c, validLanes)});
  else scatterInto<S, What>(g, pt, P, p, st, sink);
  if (What == Scatter::P2G && P.cfg.nRigids > 0) gapMinima<S>(g, P, x, st);
}

// One scatter of the sorted kernel, as the variant switches say.
template <int S, Scatter What>
void launchSorted(const Run& r, const Grid& g, const Points& pt, const Params& P) {
  const unsigned nb = blocks(r.n, kTileThreads);
  if (r.tile) scatterTiled<S, What><<<nb, kTileThreads, 0, r.stream>>>(g, pt, P);
  else if (r.minBlocks >= 8) scatterWarp<S, What, 8><<<nb, kTileThreads, 0, r.stream>>>(g, pt, P);
  else scatterWarp<S, What, 4><<<nb, kTileThreads, 0, r.stream>>>(g, pt, P);
}

__global__ void gridUpdate(Grid g, Params P, ForceSums* sums) {
  const size_t I = blockIdx.x * static_cast<size_t>(blockDim.x) + threadIdx.x;
  if (I < g.nodes) gridNode(g, P, I, sums);
}

template <int S>
__global__ void remapScatter(Grid g, Points pt, Params P) {
  const size_t p = blockIdx.x * static_cast<size_t>(blockDim.x) + threadIdx.x;
  if (p < pt.n) g2pRemapPoint<S>(g, pt, P, p);
}

__global__ void remapUpdate(Grid g, Params P) {
  const size_t I = blockIdx.x * static_cast<size_t>(blockDim.x) + threadIdx.x;
  if (I < g.nodes) remapNode(g, P, I);
}

// Sum (or max) of one value over the block; the result in thread 0.
template <bool Max>
__device__ double blockReduce(double v, double* shared) {
  for (int o = 16; o > 0; o >>= 1) {
    const double w = __shfl_down_sync(0xffffffffu, v, o);
    v = Max ? fmax(v, w) : v + w;
  }
  const int lane = threadIdx.x % 32, warp = threadIdx.x / 32;
  __syncthreads();
  if (lane == 0) shared[warp] = v;
  __syncthreads();
  if (warp == 0) {
    v = lane < static_cast<int>(blockDim.x / 32) ? shared[lane] : 0.0;
    for (int o = 16; o > 0; o >>= 1) {
      const double w = __shfl_down_sync(0xffffffffu, v, o);
      v = Max ? fmax(v, w) : v + w;
    }
  }
  return v;
}

template <int S, bool Usl>
__global__ void __launch_bounds__(kThreads) finalPass(Grid g, Points pt, Params P, Totals* t) {
  __shared__ double shared[32];
  const size_t p = blockIdx.x * static_cast<size_t>(blockDim.x) + threadIdx.x;
  FinalSums s{0.0, 0.0, 0.0};
  if (p < pt.n) {
    const int cause = g2pFinalPoint<S, Usl>(g, pt, P, p, s);
    if (cause && atomicCAS(&t->failure, 0, cause) == 0) t->failedSlot = p;
  }
  const double ek = blockReduce<false>(s.kinetic, shared);
  const double ei = blockReduce<false>(s.internal, shared);
  const double vm = blockReduce<true>(s.maxSpeed, shared);
  if (threadIdx.x == 0) {
    atomicAdd(&t->kinetic, ek);
    atomicAdd(&t->internal, ei);
    atomicMax(&t->maxSpeedBits, static_cast<unsigned long long>(bitsOf(vm)));
  }
}

// Sort keys: the base cell of each point's support.
template <int S>
__global__ void cellKeys(Grid g, Points pt, uint32_t* keys, uint32_t* slots) {
  const size_t p = blockIdx.x * static_cast<size_t>(blockDim.x) + threadIdx.x;
  if (p >= pt.n) return;
  const size_t n = pt.n;
  const Stencil<S> st = stencilAt<S>(g, pt.x[p], pt.x[n + p], pt.x[2 * n + p]);
  keys[p] = static_cast<uint32_t>(nodeIndex(g, st.bx, st.by, st.bz));
  slots[p] = static_cast<uint32_t>(p);
}

__global__ void gatherDoubles(const double* src, double* dst, const uint32_t* perm, size_t n, int comps) {
  const size_t i = blockIdx.x * static_cast<size_t>(blockDim.x) + threadIdx.x;
  if (i >= n) return;
  const size_t from = perm[i];
  for (int c = 0; c < comps; ++c) dst[c * n + i] = src[c * n + from];
}

__global__ void gatherSmall(const uint8_t* mat, uint8_t* matOut, const uint32_t* orig, uint32_t* origOut,
                            const uint32_t* perm, size_t n) {
  const size_t i = blockIdx.x * static_cast<size_t>(blockDim.x) + threadIdx.x;
  if (i >= n) return;
  matOut[i] = mat[perm[i]];
  origOut[i] = orig[perm[i]];
}

// ---------------------------------------------------------------- host side

#define NSMPM_CHECK(call)                                                                                    \
  do {                                                                                                       \
    const cudaError_t e_ = (call);                                                                           \
    if (e_ != cudaSuccess) {                                                                                 \
      std::snprintf(err, len, "%s: %s", #call, cudaGetErrorString(e_));                                      \
      return -1;                                                                                             \
    }                                                                                                        \
  } while (0)

void release(Run* r) {
  if (!r) return;
  printPhases(*r);
  for (cudaEvent_t e : r->marks)
    if (e) cudaEventDestroy(e);
  void* ptrs[] = {r->pdata, r->pscratch, r->vg, r->mat, r->matScratch, r->orig, r->origScratch, r->keys,
                  r->keysOut, r->slots, r->perm, r->cubTemp, r->rec, r->vel, r->rnormal, r->dash, r->gmin,
                  r->active, r->fix, r->totals};
  for (void* p : ptrs)
    if (p) cudaFree(p);
  if (r->hostTotals) cudaFreeHost(r->hostTotals);
  if (r->stream) cudaStreamDestroy(r->stream);
  delete r;
}

int allocate(Run& r, char* err, size_t len) {
  const size_t n = r.n, nodes = r.nodes, R = r.cfg.nRigids > 0 ? static_cast<size_t>(r.cfg.nRigids) : 1;
  NSMPM_CHECK(cudaStreamCreate(&r.stream));
  if (r.profile)
    for (cudaEvent_t& e : r.marks) NSMPM_CHECK(cudaEventCreate(&e));
  NSMPM_CHECK(cudaMalloc(&r.pdata, kPointDoubles * n * sizeof(double)));
  NSMPM_CHECK(cudaMalloc(&r.pscratch, kPointDoubles * n * sizeof(double)));
  NSMPM_CHECK(cudaMalloc(&r.vg, 3 * n * sizeof(double)));
  NSMPM_CHECK(cudaMalloc(&r.mat, n));
  NSMPM_CHECK(cudaMalloc(&r.matScratch, n));
  NSMPM_CHECK(cudaMalloc(&r.orig, n * sizeof(uint32_t)));
  NSMPM_CHECK(cudaMalloc(&r.origScratch, n * sizeof(uint32_t)));
  NSMPM_CHECK(cudaMalloc(&r.keys, n * sizeof(uint32_t)));
  NSMPM_CHECK(cudaMalloc(&r.keysOut, n * sizeof(uint32_t)));
  NSMPM_CHECK(cudaMalloc(&r.slots, n * sizeof(uint32_t)));
  NSMPM_CHECK(cudaMalloc(&r.perm, n * sizeof(uint32_t)));
  NSMPM_CHECK(cudaMalloc(&r.rec, 8 * nodes * sizeof(double)));
  NSMPM_CHECK(cudaMalloc(&r.vel, 8 * nodes * sizeof(double)));
  NSMPM_CHECK(cudaMalloc(&r.rnormal, 3 * R * nodes * sizeof(double)));
  NSMPM_CHECK(cudaMalloc(&r.dash, 3 * nodes * sizeof(double)));
  NSMPM_CHECK(cudaMalloc(&r.gmin, R * nodes * sizeof(uint64_t)));
  NSMPM_CHECK(cudaMalloc(&r.active, R * nodes));
  NSMPM_CHECK(cudaMalloc(&r.fix, nodes));
  NSMPM_CHECK(cudaMalloc(&r.totals, sizeof(Totals)));
  NSMPM_CHECK(cudaMallocHost(&r.hostTotals, sizeof(Totals)));
  NSMPM_CHECK(cub::DeviceRadixSort::SortPairs(nullptr, r.cubBytes, r.keys, r.keysOut, r.slots, r.perm,
                                              static_cast<int>(n), 0, r.keyBits, r.stream));
  NSMPM_CHECK(cudaMalloc(&r.cubTemp, r.cubBytes > 0 ? r.cubBytes : 1));
  return 0;
}

int upload(Run& r, const NsMpmParticles* in, const NsMpmGrid* grid, char* err, size_t len) {
  const size_t n = r.n, nodes = r.nodes, R = r.cfg.nRigids > 0 ? static_cast<size_t>(r.cfg.nRigids) : 1;
  const Points pt = pointsOf(r);
  NSMPM_CHECK(cudaMemcpy(pt.x, in->x, 3 * n * sizeof(double), cudaMemcpyHostToDevice));
  NSMPM_CHECK(cudaMemcpy(pt.v, in->v, 3 * n * sizeof(double), cudaMemcpyHostToDevice));
  NSMPM_CHECK(cudaMemcpy(pt.mass, in->mass, n * sizeof(double), cudaMemcpyHostToDevice));
  NSMPM_CHECK(cudaMemcpy(pt.vol0, in->vol0, n * sizeof(double), cudaMemcpyHostToDevice));
  NSMPM_CHECK(cudaMemcpy(pt.vol, in->vol, n * sizeof(double), cudaMemcpyHostToDevice));
  NSMPM_CHECK(cudaMemcpy(pt.F, in->F, 9 * n * sizeof(double), cudaMemcpyHostToDevice));
  NSMPM_CHECK(cudaMemcpy(pt.sig, in->sig, 6 * n * sizeof(double), cudaMemcpyHostToDevice));
  NSMPM_CHECK(cudaMemcpy(r.mat, in->material, n, cudaMemcpyHostToDevice));
  std::vector<uint32_t> ids(n);
  for (size_t p = 0; p < n; ++p) ids[p] = static_cast<uint32_t>(p);
  NSMPM_CHECK(cudaMemcpy(r.orig, ids.data(), n * sizeof(uint32_t), cudaMemcpyHostToDevice));
  NSMPM_CHECK(cudaMemset(r.vg, 0, 3 * n * sizeof(double)));
  NSMPM_CHECK(cudaMemset(r.rec, 0, 8 * nodes * sizeof(double)));
  NSMPM_CHECK(cudaMemset(r.vel, 0, 8 * nodes * sizeof(double)));
  NSMPM_CHECK(cudaMemset(r.rnormal, 0, 3 * R * nodes * sizeof(double)));
  NSMPM_CHECK(cudaMemset(r.active, 0, R * nodes));
  NSMPM_CHECK(cudaMemcpy(r.fix, grid->fixMask, nodes, cudaMemcpyHostToDevice));
  NSMPM_CHECK(cudaMemcpy(r.dash, grid->dashpot, 3 * nodes * sizeof(double), cudaMemcpyHostToDevice));
  fillKeys<<<blocks(R * nodes, kThreads), kThreads>>>(r.gmin, R * nodes, kNoGap);
  NSMPM_CHECK(cudaGetLastError());
  NSMPM_CHECK(cudaDeviceSynchronize());
  return 0;
}

// Points re-ordered by their base cell (every sortEvery steps of the SORTED kernel).
template <int S>
int sortPoints(Run& r, char* err, size_t len) {
  const size_t n = r.n;
  const unsigned b = blocks(n, kThreads);
  cellKeys<S><<<b, kThreads, 0, r.stream>>>(gridOf(r), pointsOf(r), r.keys, r.slots);
  NSMPM_CHECK(cudaGetLastError());
  size_t bytes = r.cubBytes;
  NSMPM_CHECK(cub::DeviceRadixSort::SortPairs(r.cubTemp, bytes, r.keys, r.keysOut, r.slots, r.perm,
                                              static_cast<int>(n), 0, r.keyBits, r.stream));
  gatherDoubles<<<b, kThreads, 0, r.stream>>>(r.pdata, r.pscratch, r.perm, n, kPointDoubles);
  gatherSmall<<<b, kThreads, 0, r.stream>>>(r.mat, r.matScratch, r.orig, r.origScratch, r.perm, n);
  NSMPM_CHECK(cudaGetLastError());
  std::swap(r.pdata, r.pscratch);
  std::swap(r.mat, r.matScratch);
  std::swap(r.orig, r.origScratch);
  return 0;
}

template <int S>
int stepWith(Run& r, const Params& P, char* err, size_t len) {
  const size_t n = r.n, nodes = r.nodes;
  const bool sorted = r.cfg.kernel == NSMPM_KERNEL_SORTED;
  mark(r, 0);
  if (sorted && n > 0 && r.steps % r.sortEvery == 0 && sortPoints<S>(r, err, len) != 0) return -1;
  mark(r, 1);
  const Grid g = gridOf(r);
  const Points pt = pointsOf(r);
  NSMPM_CHECK(cudaMemsetAsync(r.rec, 0, 8 * nodes * sizeof(double), r.stream));
  NSMPM_CHECK(cudaMemsetAsync(r.totals, 0, sizeof(Totals), r.stream));
  mark(r, 2);
  if (n > 0) {
    if (sorted) launchSorted<S, Scatter::P2G>(r, g, pt, P);
    else p2gNaive<S><<<blocks(n, kThreads), kThreads, 0, r.stream>>>(g, pt, P);
  }
  NSMPM_CHECK(cudaGetLastError());
  mark(r, 3);
  gridUpdate<<<blocks(nodes, kThreads), kThreads, 0, r.stream>>>(g, P, &r.totals->sums);
  NSMPM_CHECK(cudaGetLastError());
  mark(r, 4);
  if (r.cfg.musl) {
    if (n > 0 && sorted)
      launchSorted<S, Scatter::Remap>(r, g, pt, P);
    else if (n > 0)
      remapScatter<S><<<blocks(n, kThreads), kThreads, 0, r.stream>>>(g, pt, P);
  }
  mark(r, 5);
  if (r.cfg.musl) remapUpdate<<<blocks(nodes, kThreads), kThreads, 0, r.stream>>>(g, P);
  NSMPM_CHECK(cudaGetLastError());
  mark(r, 6);
  if (n > 0) {
    if (r.cfg.musl) finalPass<S, false><<<blocks(n, kThreads), kThreads, 0, r.stream>>>(g, pt, P, r.totals);
    else finalPass<S, true><<<blocks(n, kThreads), kThreads, 0, r.stream>>>(g, pt, P, r.totals);
  }
  NSMPM_CHECK(cudaGetLastError());
  mark(r, 7);
  NSMPM_CHECK(cudaMemcpyAsync(r.hostTotals, r.totals, sizeof(Totals), cudaMemcpyDeviceToHost, r.stream));
  NSMPM_CHECK(cudaStreamSynchronize(r.stream));
  collectPhases(r);
  ++r.steps;
  return 0;
}

// ---------------------------------------------------------------- the C interface

int probe(char* msg, size_t len) {
  int count = 0;
  const cudaError_t e = cudaGetDeviceCount(&count);
  if (e != cudaSuccess || count < 1) {
    std::snprintf(msg, len, "%s", e != cudaSuccess ? cudaGetErrorString(e) : "no CUDA device");
    return 0;
  }
  cudaDeviceProp prop;
  if (cudaGetDeviceProperties(&prop, 0) != cudaSuccess) {
    std::snprintf(msg, len, "device 0 cannot be queried");
    return 0;
  }
  std::snprintf(msg, len, "%s (sm_%d%d, %.0f GiB)", prop.name, prop.major, prop.minor,
                static_cast<double>(prop.totalGlobalMem) / (1024.0 * 1024.0 * 1024.0));
  return count;
}

void* create(const NsMpmConfig* cfg, const NsMpmParticles* in, const NsMpmGrid* grid, char* err, size_t len) {
  if (cfg->abiVersion != NSMPM_ABI_VERSION) {
    std::snprintf(err, len, "interface version %d, the plugin has %d", cfg->abiVersion, NSMPM_ABI_VERSION);
    return nullptr;
  }
  if (in->n >= 0xFFFFFFFFull) {
    std::snprintf(err, len, "%zu points: at most 2^32 - 1", in->n);
    return nullptr;
  }
  Run* r = new Run;
  r->cfg = *cfg;
  r->n = in->n;
  r->nodes = static_cast<size_t>(cfg->nodes[0]) * cfg->nodes[1] * cfg->nodes[2];
  if (r->nodes >= 0xFFFFFFFFull) {
    std::snprintf(err, len, "%zu grid nodes: at most 2^32 - 1", r->nodes);
    delete r;
    return nullptr;
  }
  r->keyBits = 1;
  while (r->keyBits < 32 && (size_t{1} << r->keyBits) < r->nodes) ++r->keyBits;
  if (const char* every = std::getenv("NEEDLESIM_MPM_CUDA_SORT_EVERY")) r->sortEvery = std::max(1, std::atoi(every));
  r->profile = std::getenv("NEEDLESIM_MPM_CUDA_PROFILE") != nullptr;
  if (const char* warp = std::getenv("NEEDLESIM_MPM_CUDA_WARP")) r->warpReduce = std::atoi(warp) != 0 ? 1 : 0;
  if (const char* tile = std::getenv("NEEDLESIM_MPM_CUDA_TILE")) r->tile = std::atoi(tile) != 0 ? 1 : 0;
  if (const char* spread = std::getenv("NEEDLESIM_MPM_CUDA_SPREAD")) r->spread = std::atoi(spread) != 0 ? 1 : 0;
  if (const char* mb = std::getenv("NEEDLESIM_MPM_CUDA_MINBLOCKS")) r->minBlocks = std::atoi(mb);
  if (allocate(*r, err, len) != 0 || upload(*r, in, grid, err, len) != 0) {
    release(r);
    return nullptr;
  }
  return r;
}

int step(void* run, const NsMpmStepIn* in, NsMpmStepOut* out, char* err, size_t len) {
  Run& r = *static_cast<Run*>(run);
  Params P;
  std::memset(&P, 0, sizeof P);
  P.cfg = r.cfg;
  P.dt = in->dt;
  P.warpReduce = r.warpReduce;
  P.tile = r.tile;
  P.spread = r.spread;
  for (int k = 0; k < NSMPM_MAX_RIGIDS; ++k) P.rigids[k] = in->rigids[k];
  const int rc = r.cfg.support == 2 ? stepWith<2>(r, P, err, len) : stepWith<3>(r, P, err, len);
  if (rc != 0) return rc;
  const Totals& t = *r.hostTotals;
  std::memset(out, 0, sizeof *out);
  out->kinetic = t.kinetic;
  out->internal = t.internal;
  out->maxSpeed = doubleOf(t.maxSpeedBits);
  for (int k = 0; k < NSMPM_MAX_RIGIDS; ++k) {
    for (int c = 0; c < 9; ++c) out->force[k][c] = t.sums.f[k][c];
    out->contactNodes[k] = t.sums.count[k];
  }
  out->failure = t.failure;
  if (t.failure) {
    uint32_t id = 0;
    NSMPM_CHECK(cudaMemcpy(&id, r.orig + t.failedSlot, sizeof id, cudaMemcpyDeviceToHost));
    out->failedPoint = id;
  }
  return 0;
}

int download(void* run, NsMpmParticles* out, char* err, size_t len) {
  Run& r = *static_cast<Run*>(run);
  const size_t n = r.n;
  r.staging.resize(kPointDoubles * n);
  r.hostOrig.resize(n);
  NSMPM_CHECK(cudaStreamSynchronize(r.stream));
  NSMPM_CHECK(cudaMemcpy(r.staging.data(), r.pdata, kPointDoubles * n * sizeof(double), cudaMemcpyDeviceToHost));
  NSMPM_CHECK(cudaMemcpy(r.hostOrig.data(), r.orig, n * sizeof(uint32_t), cudaMemcpyDeviceToHost));
  const double* s = r.staging.data();
  for (size_t i = 0; i < n; ++i) {
    const size_t p = r.hostOrig[i];
    for (size_t c = 0; c < 3; ++c) {
      out->x[c * n + p] = s[c * n + i];
      out->v[c * n + p] = s[(3 + c) * n + i];
    }
    out->vol[p] = s[8 * n + i];
    for (size_t c = 0; c < 9; ++c) out->F[c * n + p] = s[(9 + c) * n + i];
    for (size_t c = 0; c < 6; ++c) out->sig[c * n + p] = s[(18 + c) * n + i];
  }
  return 0;
}

void destroy(void* run) { release(static_cast<Run*>(run)); }

}  // namespace

extern "C" __attribute__((visibility("default"))) const NsMpmBackend* needlesim_mpm_backend(void) {
  static const NsMpmBackend b = {NSMPM_ABI_VERSION, probe, create, step, download, destroy};
  return &b;
}
