// MpmSolver on a GPU back-end (mpm_device_abi.h): the set-up and the state as
// the plain structures of the C interface, one step there per step(), and the
// particles copied back only when asked (syncFromDevice). The physics runs in
// mpm_device_kernels.hpp (CUDA plugin or host emulation).
#include <fmt/format.h>

#include <algorithm>
#include <cstdint>
#include <string>
#include <vector>

#include "needlesim/core/error.hpp"
#include "needlesim/engines/mpm/cuda/mpm_device_abi.h"
#include "needlesim/engines/mpm/mpm_solver.hpp"

namespace needlesim::mpm {

// The back-end, its run (created at the first step) and the host copies of
// the particle arrays it exchanges.
class DeviceRun {
 public:
  const NsMpmBackend* backend = nullptr;
  int kernel = 0;
  void* handle = nullptr;
  bool hostFresh = true;  // the solver's particles hold the device's state
  std::vector<double> x, v, F, sig, mass, vol0, vol;
  std::vector<std::uint8_t> mat;
  DeviceRun() = default;
  DeviceRun(const DeviceRun&) = delete;
  DeviceRun& operator=(const DeviceRun&) = delete;
  ~DeviceRun() { release(); }
  void release() {
    if (handle) backend->destroy(handle);
    handle = nullptr;
  }
  NsMpmParticles arrays() {
    return NsMpmParticles{mass.size(), x.data(),    v.data(),   F.data(),  sig.data(),
                          mass.data(), vol0.data(), vol.data(), mat.data()};
  }
};

namespace {

constexpr std::size_t kMessage = 512;

NsMpmRigid rigidOf(const RigidBody& r) {
  NsMpmRigid o{};
  o.kind = r.kind == RigidBody::Kind::Plane ? NSMPM_PLANE : NSMPM_NEEDLE;
  o.tip = r.tip == RigidBody::Tip::Conical ? NSMPM_CONICAL : r.tip == RigidBody::Tip::Bevel ? NSMPM_BEVEL : NSMPM_BLUNT;
  for (int d = 0; d < 3; ++d) {
    o.point[d] = r.point[d];
    o.normal[d] = r.normal[d];
    o.axis[d] = r.axis[d];
    o.bevelSide[d] = r.bevelSide[d];
    o.velocity[d] = r.velocity[d];
  }
  o.radius = r.radius;
  o.tipAngle = r.tipAngle;
  o.friction = r.friction;
  return o;
}

NsMpmMaterial materialOf(const MpmMaterial& m, double massScaling) {
  using materials::LawKind;
  NsMpmMaterial o{};
  o.law = m.law.kind == LawKind::Fung ? NSMPM_FUNG : NSMPM_NEO_HOOKEAN;
  o.mu = m.law.mu;
  o.gamma = m.law.gamma;
  o.c10 = m.law.C10;
  o.bulk = m.law.bulk;
  o.rho0 = m.density * massScaling;
  return o;
}

}  // namespace

std::vector<std::string> MpmSolver::deviceUnsupported() const {
  std::vector<std::string> out;
  if (cfg_.bodies > 1) out.emplace_back("a sliding inclusion (two deformable bodies in pair contact)");
  if (std::any_of(rigids_.begin(), rigids_.end(), [](const RigidBody& r) { return r.surfaceContact; }))
    out.emplace_back("model.mpm.contact: cfemp, the default (CFEMP particle-to-surface contact; the GPU path runs contact: grid)");
  if (cfg_.fbar) out.emplace_back("model.mpm.anti_locking: fbar");
  if (std::any_of(rigids_.begin(), rigids_.end(), [](const RigidBody& r) {
        return r.kind == RigidBody::Kind::Needle && r.tip == RigidBody::Tip::Bevel && r.parting;
      }))
    out.emplace_back("model.mpm.parting: tip or path for a bevel needle (the needle's cut, needle_cut.cpp; parting: none "
                     "runs the one-field contact on the GPU)");
  if (std::any_of(mats_.begin(), mats_.end(), [](const MpmMaterial& m) { return m.rigidFriction >= 0.0; }))
    out.emplace_back("regions with their own needle friction (tissue layers or inclusions with another friction coefficient)");
  for (const MpmMaterial& m : mats_)
    if (m.law.kind != materials::LawKind::Fung && m.law.kind != materials::LawKind::NeoHookean) {
      out.push_back(fmt::format("material law '{}' (the GPU path has fung and neo_hookean)", materials::lawName(m.law.kind)));
      break;
    }
  if (mats_.size() > NSMPM_MAX_MATERIALS) out.push_back(fmt::format("more than {} materials", NSMPM_MAX_MATERIALS));
  if (rigids_.size() > NSMPM_MAX_RIGIDS) out.push_back(fmt::format("more than {} rigid bodies", NSMPM_MAX_RIGIDS));
  return out;
}

void MpmSolver::attachDevice(const NsMpmBackend* backend, int kernel) {
  if (!finalized_) finalize();
  const auto missing = deviceUnsupported();
  if (!missing.empty()) throw Error("mpm: the GPU path does not implement " + missing.front());
  device_ = std::make_shared<DeviceRun>();
  device_->backend = backend;
  device_->kernel = kernel;
}

void MpmSolver::dropDeviceState() {
  if (!device_) return;
  device_->release();
  device_->hostFresh = true;
}

// The set-up and the current state as the C interface's structures, to the back-end.
void MpmSolver::uploadToDevice() {
  DeviceRun& d = *device_;
  NsMpmConfig c{};
  c.abiVersion = NSMPM_ABI_VERSION;
  c.h = cfg_.h;
  for (int k = 0; k < 3; ++k) {
    c.origin[k] = cfg_.origin[k];
    c.nodes[k] = nn_[k];
    c.gravity[k] = cfg_.gravity[k];
  }
  c.support = cfg_.shape == Shape::Linear ? 2 : 3;
  c.musl = cfg_.update == Update::MUSL ? 1 : 0;
  c.flip = cfg_.flip;
  c.contactGap = rigidGap_;
  c.kernel = d.kernel;
  c.nMaterials = static_cast<int>(mats_.size());
  for (std::size_t m = 0; m < mats_.size(); ++m) c.materials[m] = materialOf(mats_[m], cfg_.massScaling);
  c.nRigids = static_cast<int>(rigids_.size());
  const std::size_t n = size();
  d.x.resize(3 * n), d.v.resize(3 * n), d.F.resize(9 * n), d.sig.resize(6 * n);
  d.mass.resize(n), d.vol0.resize(n), d.vol.resize(n);
  d.mat.assign(mat_.begin(), mat_.end());
  for (std::size_t p = 0; p < n; ++p) {
    const Point& q = P_[p];
    for (std::size_t k = 0; k < 3; ++k) {
      d.x[k * n + p] = q.x[k];
      d.v[k * n + p] = q.v[k];
    }
    for (std::size_t k = 0; k < 9; ++k) d.F[k * n + p] = q.F[k];
    for (std::size_t k = 0; k < 6; ++k) d.sig[k * n + p] = q.sig[k];
    d.mass[p] = q.mass;
    d.vol0[p] = q.vol0;
    d.vol[p] = q.vol;
  }
  const NsMpmParticles pts = d.arrays();
  const NsMpmGrid g{bounds_.fixMask.data(), bounds_.dashpot.data()};
  char err[kMessage] = "";
  d.handle = d.backend->create(&c, &pts, &g, err, sizeof err);
  if (!d.handle) throw SolverError(fmt::format("mpm: the GPU back-end could not take the model: {}", err));
  d.hostFresh = true;
}

StepReport MpmSolver::deviceStep() {
  DeviceRun& d = *device_;
  if (!d.handle) uploadToDevice();
  NsMpmStepIn in{};
  in.dt = dt_;
  for (std::size_t r = 0; r < rigids_.size(); ++r) in.rigids[r] = rigidOf(rigids_[r]);
  NsMpmStepOut out{};
  char err[kMessage] = "";
  if (d.backend->step(d.handle, &in, &out, err, sizeof err) != 0)
    throw SolverError(fmt::format("mpm: the GPU step failed at t = {:.6g} s, step {}: {}", time_, steps_, err));
  d.hostFresh = false;
  if (out.failure) {
    syncFromDevice();
    fail(out.failedPoint, out.failure);
  }
  for (std::size_t r = 0; r < rigids_.size(); ++r) {
    RigidForce f;
    f.total = Vec3(out.force[r][0], out.force[r][1], out.force[r][2]);
    f.shaft = Vec3(out.force[r][3], out.force[r][4], out.force[r][5]);
    f.tip = Vec3(out.force[r][6], out.force[r][7], out.force[r][8]);
    f.contactNodes = out.contactNodes[r];
    rforce_[r] = f;
  }
  maxSpeed_ = out.maxSpeed;
  time_ += dt_;
  ++steps_;
  last_ = StepReport{dt_, out.kinetic, out.internal, out.maxSpeed};
  return last_;
}

void MpmSolver::syncFromDevice() {
  if (!device_ || device_->hostFresh || !device_->handle) return;
  DeviceRun& d = *device_;
  NsMpmParticles pts = d.arrays();
  char err[kMessage] = "";
  if (d.backend->download(d.handle, &pts, err, sizeof err) != 0)
    throw SolverError(fmt::format("mpm: copying the particles back from the GPU failed: {}", err));
  const std::size_t n = size();
  for (std::size_t p = 0; p < n; ++p) {
    Point& q = P_[p];
    for (std::size_t k = 0; k < 3; ++k) {
      q.x[k] = d.x[k * n + p];
      q.v[k] = d.v[k * n + p];
    }
    for (std::size_t k = 0; k < 9; ++k) q.F[k] = d.F[k * n + p];
    for (std::size_t k = 0; k < 6; ++k) q.sig[k] = d.sig[k * n + p];
    q.vol = d.vol[p];
  }
  d.hostFresh = true;
}

}  // namespace needlesim::mpm
