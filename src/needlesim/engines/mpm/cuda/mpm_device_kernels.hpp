// The physics of one MPM step per point and per node, written once for the
// CUDA kernels (mpm_cuda.cu) and their serial host emulation
// (mpm_emulation.cpp): under nvcc the functions are __host__ __device__,
// elsewhere plain inline C++. They mirror MpmSolver (mpm_solver.cpp): quadratic
// B-spline or linear weights, P2G of mass, momentum and -V sigma grad N (seed
// 000 eqs 1-3), the grid momentum update with gravity and dashpots, the rigid
// grid contact with Coulomb friction (eqs 14-22), the MUSL remap and the G2P
// update of velocity, position and F (eq 4), and the Fung-Demiray and
// neo-Hookean stresses (eqs 8-13) with the eq 27 wave speed. No Eigen, no STL.
#pragma once

#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include "needlesim/engines/mpm/cuda/mpm_device_abi.h"

#ifdef __CUDACC__
#define NSMPM_HD __host__ __device__ inline
#else
#define NSMPM_HD inline
#endif

namespace nsmpm {

// ---------------------------------------------------------------- atomics (plain on the host)

NSMPM_HD void addTo(double* p, double v) {
#ifdef __CUDA_ARCH__
  atomicAdd(p, v);
#else
  *p += v;
#endif
}

NSMPM_HD void addTo(int* p, int v) {
#ifdef __CUDA_ARCH__
  atomicAdd(p, v);
#else
  *p += v;
#endif
}

NSMPM_HD uint64_t bitsOf(double d) {
#ifdef __CUDA_ARCH__
  return static_cast<uint64_t>(__double_as_longlong(d));
#else
  uint64_t u;
  memcpy(&u, &d, sizeof u);
  return u;
#endif
}

NSMPM_HD double doubleOf(uint64_t u) {
#ifdef __CUDA_ARCH__
  return __longlong_as_double(static_cast<long long>(u));
#else
  double d;
  memcpy(&d, &u, sizeof d);
  return d;
#endif
}

// A key whose unsigned order is the order of the doubles (gap minima by atomicMin).
NSMPM_HD uint64_t orderedKey(double d) {
  const uint64_t u = bitsOf(d);
  return (u >> 63) ? ~u : (u | (uint64_t{1} << 63));
}
NSMPM_HD double fromOrderedKey(uint64_t k) { return doubleOf((k >> 63) ? (k & ~(uint64_t{1} << 63)) : ~k); }
constexpr uint64_t kNoGap = 0xFFF0000000000000ull;  // orderedKey(+inf)

NSMPM_HD void minTo(uint64_t* p, uint64_t k) {
#ifdef __CUDA_ARCH__
  atomicMin(reinterpret_cast<unsigned long long*>(p), static_cast<unsigned long long>(k));
#else
  if (k < *p) *p = k;
#endif
}

// Largest of non-negative doubles (their bits order as integers).
NSMPM_HD void maxTo(uint64_t* p, double v) {
#ifdef __CUDA_ARCH__
  atomicMax(reinterpret_cast<unsigned long long*>(p), static_cast<unsigned long long>(bitsOf(v)));
#else
  if (bitsOf(v) > *p) *p = bitsOf(v);
#endif
}

// ---------------------------------------------------------------- state views

// Particle state on the device (or host emulation): structures of arrays,
// component c of point p at [c n + p]; vg: MUSL sum_I N_Ip v_I (3 n).
struct Points {
  size_t n;
  double *x, *v, *mass, *vol0, *vol, *F, *sig, *vg;
  const uint8_t* mat;
};

// Grid records as MpmSolver's: rec 8 per node (mass, momentum 3, force 3, pad),
// vel 8 per node (v_new 3, pad, v_old or v* 3, pad); per rigid and node the gap
// minimum key, the contact flags (bit 0 acted, bit 1 within the gap, bits 2+
// part) and the normal (3).
struct Grid {
  int nx, ny, nz;
  size_t nodes;
  double h, invh, ox, oy, oz;
  double *rec, *vel;
  uint64_t* gmin;
  uint8_t* active;
  double* rnormal;
  const uint8_t* fix;
  const double* dash;
};

// Per-step parameters (passed by value to every kernel).
struct Params {
  NsMpmConfig cfg;
  NsMpmRigid rigids[NSMPM_MAX_RIGIDS];
  double dt;
  int warpReduce;  // CUDA sorted kernel: warp-level sums of runs of points in one cell before the adds
  int tile;        // CUDA sorted kernel: adds into a shared-memory tile first
  int spread;      // CUDA sorted kernel: blocks in a spread order
};

// Per rigid force sums (total 3, shaft 3, tip 3) and contact node counts.
struct ForceSums {
  double f[NSMPM_MAX_RIGIDS][9];
  int count[NSMPM_MAX_RIGIDS];
};

// ---------------------------------------------------------------- shape functions

// grid::weights: base node, weights and derivatives along one axis (xi >= 0).
template <int S>
NSMPM_HD int weights(double xi, double invh, double* w, double* dw) {
  if (S == 2) {
    const double b = static_cast<double>(static_cast<int>(xi));
    const double f = xi - b;
    w[0] = 1.0 - f;
    w[1] = f;
    dw[0] = -invh;
    dw[1] = invh;
    return static_cast<int>(b);
  }
  const double b = static_cast<double>(static_cast<int>(xi - 0.5));
  const double f = xi - b;  // in [0.5, 1.5)
  const double a0 = 1.5 - f, a1 = f - 1.0, a2 = f - 0.5;
  w[0] = 0.5 * a0 * a0;
  w[1] = 0.75 - a1 * a1;
  w[S - 1] = 0.5 * a2 * a2;
  dw[0] = -a0 * invh;
  dw[1] = -2.0 * a1 * invh;
  dw[S - 1] = a2 * invh;
  return static_cast<int>(b);
}

template <int S>
struct Stencil {
  double wx[S], wy[S], wz[S], dx[S], dy[S], dz[S];
  int bx, by, bz;
};

template <int S>
NSMPM_HD Stencil<S> stencilAt(const Grid& g, double x, double y, double z) {
  Stencil<S> s;
  s.bx = weights<S>((x - g.ox) * g.invh, g.invh, s.wx, s.dx);
  s.by = weights<S>((y - g.oy) * g.invh, g.invh, s.wy, s.dy);
  s.bz = weights<S>((z - g.oz) * g.invh, g.invh, s.wz, s.dz);
  return s;
}

NSMPM_HD size_t nodeIndex(const Grid& g, int i, int j, int k) {
  return (static_cast<size_t>(i) * static_cast<size_t>(g.ny) + static_cast<size_t>(j)) * static_cast<size_t>(g.nz) +
         static_cast<size_t>(k);
}

// ---------------------------------------------------------------- materials (materials/stress_lanes.hpp)

// J^(-1/3): Taylor start near 1 and two Newton steps, else a bit estimate and four.
NSMPM_HD double invCbrt(double J) {
  const double e = J - 1.0;
  double z;
  int steps;
  if (fabs(e) < 0.05) {
    z = 1.0 + e * (-1.0 / 3.0 + e * (2.0 / 9.0));
    steps = 2;
  } else {
    z = doubleOf(0x553ef0ff289dd796ull - bitsOf(J) / 3);
    steps = 4;
  }
  for (int it = 0; it < steps; ++it) z *= (4.0 - J * z * z * z) * (1.0 / 3.0);
  return z;
}

// Cauchy stress (Voigt 11 22 33 12 23 13), energy per reference volume W and
// wave speed sqrt((K + 4/3 mu_t) J / rho0) of the decoupled Fung-Demiray or
// neo-Hookean law at F (row major); seed 000 eqs 8-13, 27.
NSMPM_HD void hyperelasticStress(const NsMpmMaterial& L, const double* F, double* sig, double& W, double& wave) {
  const double J = F[0] * (F[4] * F[8] - F[5] * F[7]) - F[1] * (F[3] * F[8] - F[5] * F[6]) +
                   F[2] * (F[3] * F[7] - F[4] * F[6]);
  const double b00 = F[0] * F[0] + F[1] * F[1] + F[2] * F[2], b11 = F[3] * F[3] + F[4] * F[4] + F[5] * F[5],
               b22 = F[6] * F[6] + F[7] * F[7] + F[8] * F[8], b01 = F[0] * F[3] + F[1] * F[4] + F[2] * F[5],
               b12 = F[3] * F[6] + F[4] * F[7] + F[5] * F[8], b02 = F[0] * F[6] + F[1] * F[7] + F[2] * F[8];
  const double Jm13 = invCbrt(J);
  const double Jm23 = Jm13 * Jm13;
  const double trb = b00 + b11 + b22;
  const double I1b = Jm23 * trb;
  double W1, muc;
  if (L.law == NSMPM_FUNG) {
    const double x = L.gamma * (I1b - 3.0);
    const double ex = exp(x);
    W1 = 0.5 * L.mu * ex;
    const double series = x * (1.0 + x * (0.5 + x * (1.0 / 6.0 + x / 24.0)));
    const double em1 = fabs(x) < 1e-3 ? series : ex - 1.0;
    W = L.mu / (2.0 * L.gamma) * em1;
    muc = L.mu * ex * (1.0 + 2.0 * L.gamma * I1b);
  } else {
    W1 = L.c10;
    W = L.c10 * (I1b - 3.0);
    muc = 2.0 * L.c10;
  }
  const double K = L.bulk;
  W += 0.5 * K * (J - 1.0) * (J - 1.0);
  const double c = 2.0 * W1 * Jm23 / J;
  const double diag = -c * trb / 3.0 + K * (J - 1.0);
  sig[0] = c * b00 + diag;
  sig[1] = c * b11 + diag;
  sig[2] = c * b22 + diag;
  sig[3] = c * b01;
  sig[4] = c * b12;
  sig[5] = c * b02;
  const double rho = L.rho0 / J;
  wave = sqrt((K + 4.0 / 3.0 * muc) / rho);
}

// ---------------------------------------------------------------- rigid bodies (RigidBody::distance)

NSMPM_HD double dot3(const double* a, const double* b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

NSMPM_HD void axisPoint(const NsMpmRigid& rb, double* c) {
  for (int d = 0; d < 3; ++d) c[d] = rb.tip == NSMPM_BEVEL ? rb.point[d] + rb.radius * rb.bevelSide[d] : rb.point[d];
}

// Signed distance of x to the rigid (negative inside), the outward normal n
// (may be null) and the nearest part (0 shaft or plane, 1 tip).
NSMPM_HD double rigidDistance(const NsMpmRigid& rb, const double* x, double* n, int* part) {
  if (rb.kind == NSMPM_PLANE) {
    if (n)
      for (int d = 0; d < 3; ++d) n[d] = rb.normal[d];
    if (part) *part = 0;
    const double rel[3] = {x[0] - rb.point[0], x[1] - rb.point[1], x[2] - rb.point[2]};
    return dot3(rel, rb.normal);
  }
  const double* e = rb.axis;
  double c[3];
  axisPoint(rb, c);
  const double rel[3] = {x[0] - c[0], x[1] - c[1], x[2] - c[2]};
  const double s = -dot3(rel, e);
  const double rv[3] = {rel[0] + s * e[0], rel[1] + s * e[1], rel[2] + s * e[2]};
  const double r = sqrt(dot3(rv, rv));
  double er[3];
  for (int d = 0; d < 3; ++d) er[d] = r > 1e-14 ? rv[d] / r : rb.bevelSide[d];
  const double dCyl = r - rb.radius;
  double dTip, nTip[3];
  if (rb.tip == NSMPM_CONICAL) {
    const double cb = cos(rb.tipAngle), sb = sin(rb.tipAngle);
    if (s * cb + r * sb <= 0.0) {
      dTip = sqrt(dot3(rel, rel));
      for (int d = 0; d < 3; ++d) nTip[d] = dTip > 1e-14 ? rel[d] / dTip : e[d];
    } else {
      dTip = r * cb - s * sb;
      for (int d = 0; d < 3; ++d) nTip[d] = cb * er[d] + sb * e[d];
    }
  } else if (rb.tip == NSMPM_BEVEL) {
    const double st = sin(rb.tipAngle), ct = cos(rb.tipAngle);
    for (int d = 0; d < 3; ++d) nTip[d] = st * e[d] + ct * rb.bevelSide[d];
    const double xp[3] = {x[0] - rb.point[0], x[1] - rb.point[1], x[2] - rb.point[2]};
    dTip = dot3(xp, nTip);
  } else {
    for (int d = 0; d < 3; ++d) nTip[d] = e[d];
    dTip = -s;
  }
  if (dTip >= dCyl) {
    if (n)
      for (int d = 0; d < 3; ++d) n[d] = nTip[d];
    if (part) *part = 1;
    return dTip;
  }
  if (n)
    for (int d = 0; d < 3; ++d) n[d] = er[d];
  if (part) *part = 0;
  return dCyl;
}

// Contact of a node's field (mass m, velocity v, updated in place) with a
// rigid of velocity vr along normal n (eqs 14-15, 19-21); returns the impulse
// given to the tissue in imp, and whether it is non-zero.
NSMPM_HD bool rigidContact(double m, double* v, const double* n, const double* vr, double mu, double* imp) {
  const double rel[3] = {vr[0] - v[0], vr[1] - v[1], vr[2] - v[2]};
  const double vn = dot3(rel, n);
  imp[0] = imp[1] = imp[2] = 0.0;
  if (vn <= 0.0) return false;
  double dv[3] = {vn * n[0], vn * n[1], vn * n[2]};
  const double rt[3] = {rel[0] - vn * n[0], rel[1] - vn * n[1], rel[2] - vn * n[2]};
  const double st = sqrt(dot3(rt, rt));
  if (st > 0) {
    const double lim = mu * vn;
    const double scale = st > lim ? lim / st : 1.0;  // contact::coulombScale
    for (int d = 0; d < 3; ++d) dv[d] += scale * rt[d];
  }
  for (int d = 0; d < 3; ++d) {
    v[d] += dv[d];
    imp[d] = m * dv[d];
  }
  return imp[0] * imp[0] + imp[1] * imp[1] + imp[2] * imp[2] != 0.0;
}

// ---------------------------------------------------------------- particle to grid (eqs 1-3, 22)

// The gap of point x to each rigid within reach, as nodal minima over its support.
template <int S>
NSMPM_HD void gapMinima(const Grid& g, const Params& P, const double* x, const Stencil<S>& st) {
  const double reach = 2.0 * g.h + P.cfg.contactGap;
  for (int r = 0; r < P.cfg.nRigids; ++r) {
    const NsMpmRigid& rb = P.rigids[r];
    if (rb.kind == NSMPM_NEEDLE) {  // cheap bound: the distance to the shaft cylinder
      double c[3];
      axisPoint(rb, c);
      const double rel[3] = {x[0] - c[0], x[1] - c[1], x[2] - c[2]};
      const double s = dot3(rel, rb.axis);
      if (dot3(rel, rel) - s * s > (rb.radius + reach) * (rb.radius + reach)) continue;
    }
    const double gap = rigidDistance(rb, x, nullptr, nullptr);
    if (gap > reach) continue;
    const uint64_t key = orderedKey(gap);
    uint64_t* gm = g.gmin + static_cast<size_t>(r) * g.nodes;
    for (int i = 0; i < S; ++i)
      for (int j = 0; j < S; ++j)
        for (int k = 0; k < S; ++k) minTo(gm + nodeIndex(g, st.bx + i, st.by + j, st.bz + k), key);
  }
}

// Adds into the global grid records (atomics on the device).
struct GlobalSink {
  const Grid* g;
  NSMPM_HD double* node(int i, int j, int k) const { return g->rec + 8 * nodeIndex(*g, i, j, k); }
  NSMPM_HD void add(double* r, int c, double v) const { addTo(r + c, v); }
};

// MpmSolver::scatterPoint: mass, momentum and -V sigma : grad N of point p
// over its support st, in its tensor-product form, into sink (entries 0-6 of
// a node's record: mass, momentum, force).
template <int S, class Sink>
NSMPM_HD void scatterPoint(const Points& pt, size_t p, const Stencil<S>& st, const Sink& sink) {
  const size_t n = pt.n;
  const double m = pt.mass[p];
  const double q[4] = {m, m * pt.v[p], m * pt.v[n + p], m * pt.v[2 * n + p]};
  const double V = -pt.vol[p];
  const double* sg = pt.sig;
  const double s00 = V * sg[p], s11 = V * sg[n + p], s22 = V * sg[2 * n + p];
  const double s01 = V * sg[3 * n + p], s12 = V * sg[4 * n + p], s02 = V * sg[5 * n + p];
  const double S0[3] = {s00, s01, s02}, S1[3] = {s01, s11, s12}, S2[3] = {s02, s12, s22};
  for (int i = 0; i < S; ++i)
    for (int j = 0; j < S; ++j) {
      const double wij = st.wx[i] * st.wy[j], gx = st.dx[i] * st.wy[j], gy = st.wx[i] * st.dy[j];
      double a0[4], a1[3], b1[3];
      for (int c = 0; c < 4; ++c) a0[c] = wij * q[c];
      for (int c = 0; c < 3; ++c) {
        a1[c] = gx * S0[c] + gy * S1[c];
        b1[c] = wij * S2[c];
      }
      for (int k = 0; k < S; ++k) {
        double* r = sink.node(st.bx + i, st.by + j, st.bz + k);
        for (int c = 0; c < 4; ++c) sink.add(r, c, st.wz[k] * a0[c]);
        for (int c = 0; c < 3; ++c) sink.add(r, 4 + c, st.wz[k] * a1[c] + st.dz[k] * b1[c]);
      }
    }
}

// P2G of point p into the global records, and its gaps to the rigids.
template <int S>
NSMPM_HD void p2gPoint(const Grid& g, const Points& pt, const Params& P, size_t p) {
  const size_t n = pt.n;
  const double x[3] = {pt.x[p], pt.x[n + p], pt.x[2 * n + p]};
  const Stencil<S> st = stencilAt<S>(g, x[0], x[1], x[2]);
  scatterPoint<S>(pt, p, st, GlobalSink{&g});
  if (P.cfg.nRigids > 0) gapMinima<S>(g, P, x, st);
}

// ---------------------------------------------------------------- grid update (eq 3, contact, faces)

// Node I: v_old = p / m and v_new = (p + (f + m g) dt) / (m + d dt) (eq 3 with
// the dashpots), MUSL: the momentum lanes cleared for the remap; the rigid
// contact where a point lies within the eq 22 gap (its impulse, as the force
// on the rigid, into sums); then the fixed components. Resets the gap minima.
NSMPM_HD void gridNode(const Grid& g, const Params& P, size_t I, ForceSums* sums) {
  double* r = g.rec + 8 * I;
  double* v = g.vel + 8 * I;
  const int R = P.cfg.nRigids;
  const double m = r[0];
  if (!(m > 0)) {
    for (int c = 0; c < 8; ++c) v[c] = 0.0;
    for (int k = 0; k < R; ++k) {
      g.gmin[static_cast<size_t>(k) * g.nodes + I] = kNoGap;
      g.active[static_cast<size_t>(k) * g.nodes + I] = 0;
    }
    return;
  }
  const double dt = P.dt;
  const double* d = g.dash + 3 * I;
  for (int c = 0; c < 3; ++c) {
    v[4 + c] = r[1 + c] / m;
    v[c] = (r[1 + c] + (r[4 + c] + m * P.cfg.gravity[c]) * dt) / (m + d[c] * dt);
  }
  v[3] = v[7] = 0.0;
  if (P.cfg.musl) r[1] = r[2] = r[3] = 0.0;
  if (R > 0) {
    const size_t nz = static_cast<size_t>(g.nz), nyz = static_cast<size_t>(g.ny) * nz;
    const double xI[3] = {g.ox + g.h * static_cast<double>(static_cast<int>(I / nyz)),
                          g.oy + g.h * static_cast<double>(static_cast<int>((I / nz) % static_cast<size_t>(g.ny))),
                          g.oz + g.h * static_cast<double>(static_cast<int>(I % nz))};
    for (int k = 0; k < R; ++k) {
      const size_t at = static_cast<size_t>(k) * g.nodes + I;
      g.active[at] = 0;
      const double gm = fromOrderedKey(g.gmin[at]);
      g.gmin[at] = kNoGap;
      if (!(gm < P.cfg.contactGap)) continue;
      const NsMpmRigid& rb = P.rigids[k];
      double n[3], imp[3];
      int part = 0;
      rigidDistance(rb, xI, n, &part);
      for (int c = 0; c < 3; ++c) g.rnormal[3 * at + c] = n[c];
      const bool acted = rigidContact(m, v, n, rb.velocity, rb.friction, imp);
      g.active[at] = static_cast<uint8_t>((acted ? 1 : 0) | 2 | (part << 2));
      if (!acted) continue;
      for (int c = 0; c < 3; ++c) {
        addTo(&sums->f[k][c], -imp[c] / dt);
        addTo(&sums->f[k][3 * (part + 1) + c], -imp[c] / dt);
      }
      addTo(&sums->count[k], 1);
    }
  }
  const uint8_t mask = g.fix[I];
  for (int c = 0; c < 3; ++c)
    if (mask & (1 << c)) v[c] = 0.0;
}

// MUSL remap at node I: v* = p / m, the rigid contact along the normal of the
// first update where it was within the gap, the fixed components; clears the record.
NSMPM_HD void remapNode(const Grid& g, const Params& P, size_t I) {
  double* r = g.rec + 8 * I;
  double* v = g.vel + 8 * I;
  const double m = r[0];
  if (!(m > 0)) {
    v[4] = v[5] = v[6] = 0.0;
    return;
  }
  for (int c = 0; c < 3; ++c) v[4 + c] = r[1 + c] / m;
  for (int k = 0; k < P.cfg.nRigids; ++k) {
    const size_t at = static_cast<size_t>(k) * g.nodes + I;
    if (!(g.active[at] & 2)) continue;
    double imp[3];
    rigidContact(m, v + 4, g.rnormal + 3 * at, P.rigids[k].velocity, P.rigids[k].friction, imp);
  }
  const uint8_t mask = g.fix[I];
  for (int c = 0; c < 3; ++c)
    if (mask & (1 << c)) v[4 + c] = 0.0;
}

// ---------------------------------------------------------------- grid to particle (eq 4)

// MUSL: the new point velocity (FLIP blended with PIC), sum N v_new kept for
// the position update, and the remap of its momentum into the records.
template <int S, class Sink>
NSMPM_HD void g2pRemapPoint(const Grid& g, const Points& pt, const Params& P, size_t p, const Stencil<S>& st,
                            const Sink& sink) {
  const size_t n = pt.n;
  double an[3] = {0, 0, 0}, ao[3] = {0, 0, 0};
  for (int i = 0; i < S; ++i)
    for (int j = 0; j < S; ++j) {
      const double* v = g.vel + 8 * nodeIndex(g, st.bx + i, st.by + j, st.bz);
      double sn[3], so[3];
      for (int c = 0; c < 3; ++c) {
        sn[c] = st.wz[0] * v[c];
        so[c] = st.wz[0] * v[4 + c];
      }
      for (int k = 1; k < S; ++k)
        for (int c = 0; c < 3; ++c) {
          sn[c] += st.wz[k] * v[8 * k + c];
          so[c] += st.wz[k] * v[8 * k + 4 + c];
        }
      const double wij = st.wx[i] * st.wy[j];
      for (int c = 0; c < 3; ++c) {
        an[c] += wij * sn[c];
        ao[c] += wij * so[c];
      }
    }
  const double flip = P.cfg.flip, m = pt.mass[p];
  double q[3];
  for (int c = 0; c < 3; ++c) {
    const double vc = flip * (pt.v[c * n + p] + (an[c] - ao[c])) + (1 - flip) * an[c];
    pt.v[c * n + p] = vc;
    pt.vg[c * n + p] = an[c];
    q[c] = m * vc;
  }
  for (int i = 0; i < S; ++i)
    for (int j = 0; j < S; ++j) {
      const double wij = st.wx[i] * st.wy[j];
      for (int k = 0; k < S; ++k) {
        double* r = sink.node(st.bx + i, st.by + j, st.bz + k);
        for (int c = 0; c < 3; ++c) sink.add(r, 1 + c, st.wz[k] * (wij * q[c]));
      }
    }
}

template <int S>
NSMPM_HD void g2pRemapPoint(const Grid& g, const Points& pt, const Params& P, size_t p) {
  const size_t n = pt.n;
  const Stencil<S> st = stencilAt<S>(g, pt.x[p], pt.x[n + p], pt.x[2 * n + p]);
  g2pRemapPoint<S>(g, pt, P, p, st, GlobalSink{&g});
}

// Totals of the final pass over the points.
struct FinalSums {
  double kinetic, internal, maxSpeed;
};

// The final pass at point p: velocity (USL), position, F <- (I + dt L) F, the
// volume, the checks (returns a failure cause, 0 when it goes on), and the
// stress; kinetic, strain energy and wave plus point speed into s.
template <int S, bool Usl>
NSMPM_HD int g2pFinalPoint(const Grid& g, const Points& pt, const Params& P, size_t p, FinalSums& s) {
  const size_t n = pt.n;
  const Stencil<S> st = stencilAt<S>(g, pt.x[p], pt.x[n + p], pt.x[2 * n + p]);
  const int go = Usl ? 0 : 4;
  double an[3] = {0, 0, 0}, ao[3] = {0, 0, 0}, Lx[3] = {0, 0, 0}, Ly[3] = {0, 0, 0}, Lz[3] = {0, 0, 0};
  for (int i = 0; i < S; ++i)
    for (int j = 0; j < S; ++j) {
      const double* v = g.vel + 8 * nodeIndex(g, st.bx + i, st.by + j, st.bz);
      double sw[3], sd[3], so[3] = {0, 0, 0};
      for (int c = 0; c < 3; ++c) {
        sw[c] = st.wz[0] * v[go + c];
        sd[c] = st.dz[0] * v[go + c];
        if (Usl) so[c] = st.wz[0] * v[4 + c];
      }
      for (int k = 1; k < S; ++k)
        for (int c = 0; c < 3; ++c) {
          sw[c] += st.wz[k] * v[8 * k + go + c];
          sd[c] += st.dz[k] * v[8 * k + go + c];
          if (Usl) so[c] += st.wz[k] * v[8 * k + 4 + c];
        }
      const double wij = st.wx[i] * st.wy[j], gx = st.dx[i] * st.wy[j], gy = st.wx[i] * st.dy[j];
      for (int c = 0; c < 3; ++c) {
        if (Usl) {
          an[c] += wij * sw[c];
          ao[c] += wij * so[c];
        }
        Lx[c] += gx * sw[c];
        Ly[c] += gy * sw[c];
        Lz[c] += wij * sd[c];
      }
    }
  const double dt = P.dt, flip = P.cfg.flip;
  double acc[3];
  for (int c = 0; c < 3; ++c) {
    if (Usl) {
      pt.v[c * n + p] = flip * (pt.v[c * n + p] + (an[c] - ao[c])) + (1 - flip) * an[c];
      acc[c] = an[c];
    } else {
      acc[c] = pt.vg[c * n + p];
    }
    pt.x[c * n + p] += dt * acc[c];
  }
  const double L[9] = {Lx[0], Ly[0], Lz[0], Lx[1], Ly[1], Lz[1], Lx[2], Ly[2], Lz[2]};
  double F[9], Fn[9];
  for (int c = 0; c < 9; ++c) F[c] = pt.F[c * n + p];
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
      Fn[3 * r + c] = F[3 * r + c] + dt * (L[3 * r] * F[c] + L[3 * r + 1] * F[3 + c] + L[3 * r + 2] * F[6 + c]);
  for (int c = 0; c < 9; ++c) pt.F[c * n + p] = Fn[c];
  const double J = Fn[0] * (Fn[4] * Fn[8] - Fn[5] * Fn[7]) - Fn[1] * (Fn[3] * Fn[8] - Fn[5] * Fn[6]) +
                   Fn[2] * (Fn[3] * Fn[7] - Fn[4] * Fn[6]);
  pt.vol[p] = pt.vol0[p] * J;
  const double vx = pt.v[p], vy = pt.v[n + p], vz = pt.v[2 * n + p];
  const double speed2 = vx * vx + vy * vy + vz * vz;
  const double xs[3] = {pt.x[p], pt.x[n + p], pt.x[2 * n + p]};
  if (!isfinite(speed2) || !isfinite(xs[0] + xs[1] + xs[2])) return 2;
  if (!(J > 0.0) || !isfinite(J)) return 1;
  const double sh = S == 2 ? 0.0 : 0.5;
  const double o[3] = {g.ox, g.oy, g.oz};
  const int nn[3] = {g.nx, g.ny, g.nz};
  for (int d = 0; d < 3; ++d) {
    const double xi = (xs[d] - o[d]) * g.invh - sh;
    if (!(xi >= 0.0 && xi < nn[d] - S + 1.0)) return 3;
  }
  s.kinetic += 0.5 * pt.mass[p] * speed2;
  double sig[6], W, wave;
  hyperelasticStress(P.cfg.materials[pt.mat[p]], Fn, sig, W, wave);
  for (int c = 0; c < 6; ++c) pt.sig[c * n + p] = sig[c];
  s.internal += pt.vol0[p] * W;
  const double sp = wave + sqrt(speed2);
  if (sp > s.maxSpeed) s.maxSpeed = sp;
  return 0;
}

}  // namespace nsmpm
