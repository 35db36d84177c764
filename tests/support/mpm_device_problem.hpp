#pragma once
// Small needle-in-block problems run twice, by MpmSolver on the CPU and by a
// GPU back-end (the CUDA plugin or its host emulation), for the agreement
// tests of the GPU path (tests/mpm/test_mpm_device_emulation.cpp, tests/gpu/test_gpu_mpm.cpp).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <vector>

#include "needlesim/engines/mpm/mpm_solver.hpp"

namespace needlesim::mpm::test {

struct DeviceCase {
  const char* name;
  Shape shape = Shape::BSpline2;
  Update update = Update::MUSL;
  RigidBody::Tip tip = RigidBody::Tip::Conical;
  bool gravity = false;
  bool twoBlocks = false;  // a Fung block on a neo-Hookean one (one body, two materials)
  double flip = 1.0;
};

inline MpmMaterial deviceFung() {
  MpmMaterial m;
  m.law.kind = materials::LawKind::Fung;
  m.law.mu = 10e3;
  m.law.gamma = 1.0;
  m.law.bulk = 196.7e3;  // nu = 0.475
  m.density = 1000;
  return m;
}

inline MpmMaterial deviceNeoHookean() {
  MpmMaterial m;
  m.law.kind = materials::LawKind::NeoHookean;
  m.law.C10 = 8e3;
  m.law.bulk = 300e3;
  m.density = 1100;
  return m;
}

// A 4 x 3 x 3 mm block (dp 0.25 mm, h 0.5 mm, 2304 points), a 20 G needle
// entering along x at 20 mm/s from 0.3 mm deep; exit face fixed, sides
// roller, top and bottom non-reflecting (with gravity: a roller floor).
inline std::unique_ptr<MpmSolver> deviceProblem(const DeviceCase& c, double scale = 1.0) {
  const double L = 4e-3 * scale, W = 3e-3 * scale, h = 0.5e-3, dp = 0.25e-3;
  MpmConfig cfg;
  cfg.h = h;
  cfg.origin = Vec3(-3 * h, -3 * h, -3 * h);
  cfg.cells = {static_cast<int>(std::lround(L / h)) + 6, static_cast<int>(std::lround(W / h)) + 6,
               static_cast<int>(std::lround(W / h)) + 6};
  cfg.shape = c.shape;
  cfg.update = c.update;
  cfg.flip = c.flip;
  cfg.massScaling = 1e4;
  cfg.threads = 1;
  cfg.boxLo = Vec3(0, 0, 0);
  cfg.boxHi = Vec3(L, W, W);
  cfg.faces = {FaceBC::Free, FaceBC::Fixed, FaceBC::Roller, FaceBC::Roller, FaceBC::NonReflecting,
               FaceBC::NonReflecting};
  if (c.gravity) {  // resting on a roller floor
    cfg.gravity = Vec3(0, 0, -9.81);
    cfg.faces[4] = FaceBC::Roller;
  }
  auto s = std::make_unique<MpmSolver>(cfg);
  s->addMaterial(deviceFung());
  s->addMaterial(deviceNeoHookean());
  if (c.twoBlocks) {
    s->addBlock(Vec3(0, 0, 0), Vec3(L, W, 0.5 * W), dp, 1, 0);
    s->addBlock(Vec3(0, 0, 0.5 * W), Vec3(L, W, W), dp, 0, 0);
  } else {
    s->addBlock(Vec3(0, 0, 0), Vec3(L, W, W), dp, 0, 0);
  }
  RigidBody n;
  n.kind = RigidBody::Kind::Needle;
  n.tip = c.tip;
  n.radius = 0.45e-3;
  n.tipAngle = c.tip == RigidBody::Tip::Bevel ? 0.349 : 0.35;
  n.axis = Vec3::UnitX();
  n.bevelSide = Vec3::UnitY();
  n.point = Vec3(0.3e-3, 0.5 * W + 0.1e-3, 0.5 * W - 0.05e-3);
  n.velocity = Vec3(20e-3, 0, 0);
  n.friction = 0.255;
  s->addRigid(n);
  s->finalize();
  return s;
}

// One step with the needle moving at its velocity (placed for the step, then advanced by dt).
inline void stepWithNeedle(MpmSolver& s) {
  const StepReport r = s.step();
  s.rigid(0).point += r.dt * s.rigid(0).velocity;
}

// The largest relative difference of the rigid force totals over `steps`
// steps (relative to |F_cpu|, 1e-12 N floor), and the largest contact-node
// count and force the CPU run saw.
struct Agreement {
  double worst = 0.0;
  int worstStep = -1;
  int maxContactNodes = 0;
  double maxForce = 0.0;
  double worstPosition = 0.0;  // largest point position difference at the end, m
};

inline Agreement compareRuns(MpmSolver& cpu, MpmSolver& dev, int steps) {
  Agreement a;
  for (int k = 0; k < steps; ++k) {
    stepWithNeedle(cpu);
    stepWithNeedle(dev);
    const RigidForce &fc = cpu.rigidForce(0), &fd = dev.rigidForce(0);
    const double scale = std::max(fc.total.norm(), 1e-12);
    const double d = std::max({(fd.total - fc.total).norm(), (fd.tip - fc.tip).norm(), (fd.shaft - fc.shaft).norm()});
    if (d / scale > a.worst) {
      a.worst = d / scale;
      a.worstStep = k;
    }
    a.maxContactNodes = std::max(a.maxContactNodes, fc.contactNodes);
    a.maxForce = std::max(a.maxForce, fc.total.norm());
  }
  dev.syncFromDevice();
  for (std::size_t p = 0; p < cpu.size(); ++p)
    a.worstPosition = std::max(a.worstPosition, (cpu.position(p) - dev.position(p)).norm());
  return a;
}

// Then `steps` more steps: the largest force difference over the peak force
// of the CPU run (peak0: the peak so far).
inline double compareHistory(MpmSolver& cpu, MpmSolver& dev, int steps, double peak0, double& peak) {
  peak = peak0;
  double worst = 0.0;
  for (int k = 0; k < steps; ++k) {
    stepWithNeedle(cpu);
    stepWithNeedle(dev);
    peak = std::max(peak, cpu.rigidForce(0).total.norm());
    worst = std::max(worst, (cpu.rigidForce(0).total - dev.rigidForce(0).total).norm());
  }
  return worst / peak;
}

}  // namespace needlesim::mpm::test
