// Host emulation of the CUDA MPM step (mpm_cuda.cu): the same per-point and
// per-node functions (mpm_device_kernels.hpp) in serial loops over host
// arrays, behind the same C interface (mpm_device_abi.h), so the physics of the
// GPU path is tested against MpmSolver on machines without a GPU.
#include "needlesim/engines/mpm/cuda/mpm_emulation.hpp"

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <vector>

#include "needlesim/engines/mpm/cuda/mpm_device_kernels.hpp"

namespace needlesim::mpm {
namespace {

struct EmulatedRun {
  NsMpmConfig cfg{};
  std::vector<double> x, v, mass, vol0, vol, F, sig, vg;
  std::vector<std::uint8_t> mat;
  std::vector<double> rec, vel, rnormal, dash;
  std::vector<std::uint64_t> gmin;
  std::vector<std::uint8_t> active, fix;
  nsmpm::Grid grid{};
  nsmpm::Points points{};
};

void copyIn(std::vector<double>& to, const double* from, std::size_t count) { to.assign(from, from + count); }

void* create(const NsMpmConfig* cfg, const NsMpmParticles* in, const NsMpmGrid* g, char* err, std::size_t len) {
  if (cfg->abiVersion != NSMPM_ABI_VERSION) {
    std::snprintf(err, len, "interface version %d, the emulation has %d", cfg->abiVersion, NSMPM_ABI_VERSION);
    return nullptr;
  }
  auto* r = new EmulatedRun;
  r->cfg = *cfg;
  const std::size_t n = in->n;
  copyIn(r->x, in->x, 3 * n);
  copyIn(r->v, in->v, 3 * n);
  copyIn(r->F, in->F, 9 * n);
  copyIn(r->sig, in->sig, 6 * n);
  copyIn(r->mass, in->mass, n);
  copyIn(r->vol0, in->vol0, n);
  copyIn(r->vol, in->vol, n);
  r->vg.assign(3 * n, 0.0);
  r->mat.assign(in->material, in->material + n);
  const std::size_t nodes = static_cast<std::size_t>(cfg->nodes[0]) * cfg->nodes[1] * cfg->nodes[2];
  const std::size_t R = static_cast<std::size_t>(cfg->nRigids);
  r->rec.assign(8 * nodes, 0.0);
  r->vel.assign(8 * nodes, 0.0);
  r->gmin.assign(std::max<std::size_t>(R, 1) * nodes, nsmpm::kNoGap);
  r->active.assign(std::max<std::size_t>(R, 1) * nodes, 0);
  r->rnormal.assign(3 * std::max<std::size_t>(R, 1) * nodes, 0.0);
  r->fix.assign(g->fixMask, g->fixMask + nodes);
  copyIn(r->dash, g->dashpot, 3 * nodes);
  r->grid = nsmpm::Grid{cfg->nodes[0], cfg->nodes[1], cfg->nodes[2], nodes, cfg->h, 1.0 / cfg->h,
                        cfg->origin[0], cfg->origin[1], cfg->origin[2], r->rec.data(), r->vel.data(),
                        r->gmin.data(), r->active.data(), r->rnormal.data(), r->fix.data(), r->dash.data()};
  r->points = nsmpm::Points{n, r->x.data(), r->v.data(), r->mass.data(), r->vol0.data(), r->vol.data(),
                            r->F.data(), r->sig.data(), r->vg.data(), r->mat.data()};
  return r;
}

// One step in the order of the kernels: clear, P2G, grid update, (MUSL: remap
// P2G, remap update), final G2P.
template <int S>
int stepWith(EmulatedRun& r, const nsmpm::Params& P, NsMpmStepOut* out) {
  const nsmpm::Grid& g = r.grid;
  const nsmpm::Points& pt = r.points;
  std::fill(r.rec.begin(), r.rec.end(), 0.0);
  for (std::size_t p = 0; p < pt.n; ++p) nsmpm::p2gPoint<S>(g, pt, P, p);
  nsmpm::ForceSums sums{};
  for (std::size_t I = 0; I < g.nodes; ++I) nsmpm::gridNode(g, P, I, &sums);
  if (r.cfg.musl) {
    for (std::size_t p = 0; p < pt.n; ++p) nsmpm::g2pRemapPoint<S>(g, pt, P, p);
    for (std::size_t I = 0; I < g.nodes; ++I) nsmpm::remapNode(g, P, I);
  }
  nsmpm::FinalSums fs{0.0, 0.0, 0.0};
  for (std::size_t p = 0; p < pt.n; ++p) {
    const int cause = r.cfg.musl ? nsmpm::g2pFinalPoint<S, false>(g, pt, P, p, fs)
                                 : nsmpm::g2pFinalPoint<S, true>(g, pt, P, p, fs);
    if (cause && !out->failure) {
      out->failure = cause;
      out->failedPoint = p;
    }
  }
  out->kinetic = fs.kinetic;
  out->internal = fs.internal;
  out->maxSpeed = fs.maxSpeed;
  for (int k = 0; k < NSMPM_MAX_RIGIDS; ++k) {
    for (int c = 0; c < 9; ++c) out->force[k][c] = sums.f[k][c];
    out->contactNodes[k] = sums.count[k];
  }
  return 0;
}

int step(void* run, const NsMpmStepIn* in, NsMpmStepOut* out, char*, std::size_t) {
  auto& r = *static_cast<EmulatedRun*>(run);
  nsmpm::Params P{};
  P.cfg = r.cfg;
  P.dt = in->dt;
  for (int k = 0; k < NSMPM_MAX_RIGIDS; ++k) P.rigids[k] = in->rigids[k];
  *out = NsMpmStepOut{};
  return r.cfg.support == 2 ? stepWith<2>(r, P, out) : stepWith<3>(r, P, out);
}

int download(void* run, NsMpmParticles* out, char*, std::size_t) {
  const auto& r = *static_cast<const EmulatedRun*>(run);
  std::copy(r.x.begin(), r.x.end(), out->x);
  std::copy(r.v.begin(), r.v.end(), out->v);
  std::copy(r.F.begin(), r.F.end(), out->F);
  std::copy(r.sig.begin(), r.sig.end(), out->sig);
  std::copy(r.vol.begin(), r.vol.end(), out->vol);
  return 0;
}

void destroy(void* run) { delete static_cast<EmulatedRun*>(run); }

int probe(char* msg, std::size_t len) {
  std::snprintf(msg, len, "host emulation of the CUDA kernels (serial)");
  return 1;
}

}  // namespace

const NsMpmBackend* emulationBackend() {
  static const NsMpmBackend b{NSMPM_ABI_VERSION, probe, create, step, download, destroy};
  return &b;
}

}  // namespace needlesim::mpm
