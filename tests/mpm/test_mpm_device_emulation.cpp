// The physics of the GPU path (engines/mpm/cuda/mpm_device_kernels.hpp) run
// serially by the host emulation against MpmSolver: the rigid needle's force
// within 1e-6 relative over the first 100 steps (a different order of the
// same sums: rounding only), on single and two-material blocks, both shape
// functions and both update schemes; and the refusals of what the GPU path lacks.
#include <gtest/gtest.h>

#include <cstdlib>

#include "../support/mpm_device_problem.hpp"
#include "mpm_test_scenario.hpp"
#include "needlesim/core/error.hpp"
#include "needlesim/engines/mpm/cuda/mpm_emulation.hpp"

namespace needlesim::mpm {
namespace {

using test::DeviceCase;

class DeviceEmulation : public ::testing::TestWithParam<DeviceCase> {};

TEST_P(DeviceEmulation, RigidForceMatchesCpuOverFirstHundredSteps) {
  const DeviceCase c = GetParam();
  auto cpu = test::deviceProblem(c);
  auto dev = test::deviceProblem(c);
  dev->attachDevice(emulationBackend());
  const test::Agreement a = test::compareRuns(*cpu, *dev, 100);
  std::printf("%s: worst relative force difference %.3g (step %d), %d contact nodes, |F| up to %.3g N, "
              "positions within %.3g m\n",
              c.name, a.worst, a.worstStep, a.maxContactNodes, a.maxForce, a.worstPosition);
  EXPECT_GT(a.maxContactNodes, 10);  // the needle is in contact: the comparison compares forces
  EXPECT_GT(a.maxForce, 1e-6);
  EXPECT_LT(a.worst, 1e-6);
  EXPECT_LT(a.worstPosition, 1e-12);  // 1e-9 of the 1 mm scale
  // Steps 100-140 (the tip to the exit face): the force history (the GPU test's tolerance, 1e-4 of the peak).
  double peak = 0.0;
  const double later = test::compareHistory(*cpu, *dev, 40, a.maxForce, peak);
  std::printf("%s: steps 100-140: largest force difference %.3g of the peak %.3g N\n", c.name, later, peak);
  EXPECT_LT(later, 1e-4);
}

INSTANTIATE_TEST_SUITE_P(
    Cases, DeviceEmulation,
    ::testing::Values(DeviceCase{"bspline_musl_conical"},
                      DeviceCase{"linear_musl_bevel_gravity", Shape::Linear, Update::MUSL, RigidBody::Tip::Bevel, true,
                                 false, 0.95},
                      DeviceCase{"bspline_usl_conical", Shape::BSpline2, Update::USL},
                      DeviceCase{"two_blocks_bspline_musl_blunt", Shape::BSpline2, Update::MUSL,
                                 RigidBody::Tip::Blunt, false, true}),
    [](const auto& info) { return std::string(info.param.name); });

// The steps run on the back-end, and the particles come back only on syncFromDevice.
TEST(DeviceEmulationState, ParticlesComeBackOnSync) {
  auto dev = test::deviceProblem(DeviceCase{"sync"});
  dev->attachDevice(emulationBackend());
  const Vec3 x0 = dev->position(0);
  for (int k = 0; k < 5; ++k) test::stepWithNeedle(*dev);
  EXPECT_TRUE(dev->onDevice());
  EXPECT_EQ(dev->position(0), x0);  // host copy untouched until the sync
  dev->syncFromDevice();
  EXPECT_EQ(dev->steps(), 5);
  EXPECT_NE(dev->position(0), x0);  // the block sags and is pushed
}

TEST(DeviceEmulationState, RefusesWhatTheGpuPathLacks) {
  MpmConfig cfg;
  cfg.h = 1e-3;
  cfg.cells = {8, 8, 8};
  cfg.bodies = 2;
  cfg.fbar = true;
  MpmSolver s(cfg);
  s.addMaterial(test::deviceFung());
  s.addBlock(Vec3(2e-3, 2e-3, 2e-3), Vec3(4e-3, 4e-3, 4e-3), 0.5e-3, 0, 0);
  s.addBlock(Vec3(4e-3, 2e-3, 2e-3), Vec3(6e-3, 4e-3, 4e-3), 0.5e-3, 0, 1);
  RigidBody n;
  n.kind = RigidBody::Kind::Needle;
  n.radius = 0.4e-3;
  n.surfaceContact = true;
  s.addRigid(n);
  s.finalize();
  const auto missing = s.deviceUnsupported();
  ASSERT_EQ(missing.size(), 3u);
  EXPECT_NE(missing[0].find("two deformable bodies"), std::string::npos);
  EXPECT_NE(missing[1].find("model.mpm.contact: cfemp"), std::string::npos);
  EXPECT_NE(missing[2].find("model.mpm.anti_locking: fbar"), std::string::npos);
  EXPECT_THROW(s.attachDevice(emulationBackend()), Error);
}

// model.mpm.device: cuda with what the GPU path lacks: an InputError on
// model.mpm.device naming each (before looking for the plugin).
TEST(DeviceScenario, RefusesCfempAndFbarOnTheGpu) {
  try {
    mpm_test::runText(mpm_test::smallScenario("    device: cuda\n    contact: cfemp\n    anti_locking: fbar\n"));
    FAIL() << "ran";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_EQ(e.field(), "model.mpm.device");
    EXPECT_NE(m.find("model.mpm.contact: cfemp"), std::string::npos) << m;
    EXPECT_NE(m.find("model.mpm.anti_locking: fbar"), std::string::npos) << m;
  }
}

// No plugin where it is looked for: an InputError naming the places.
TEST(DeviceScenario, RefusesWithoutThePlugin) {
  setenv("NEEDLESIM_MPM_CUDA_PLUGIN", "/nonexistent/libneedlesim_mpm_cuda.so", 1);
  try {
    mpm_test::runText(mpm_test::smallScenario("    device: cuda\n    contact: grid\n"));
    FAIL() << "ran";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_EQ(e.field(), "model.mpm.device");
    EXPECT_NE(m.find("no CUDA plugin"), std::string::npos) << m;
    EXPECT_NE(m.find("/nonexistent/libneedlesim_mpm_cuda.so"), std::string::npos) << m;
  }
  unsetenv("NEEDLESIM_MPM_CUDA_PLUGIN");
}

}  // namespace
}  // namespace needlesim::mpm
