// The CUDA back-end of the MPM step (libneedlesim_mpm_cuda.so) against
// MpmSolver on the CPU: the rigid needle's force within 1e-6 relative over
// the first 100 steps (atomics only reorder sums), then the same force
// history within 1e-4 of its peak; on small needle-in-block problems (both
// P2G kernels) and on examples/mpm/quick_needle_block.yaml through the
// engine. Skipped with the reason where the plugin or a CUDA device is missing.
#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <sstream>

#include "../support/mpm_device_problem.hpp"
#include "needlesim/core/error.hpp"
#include "needlesim/engines/memory_sink.hpp"
#include "needlesim/engines/mpm/cuda/plugin_loader.hpp"
#include "needlesim/scenario/reader.hpp"

namespace needlesim::mpm {
namespace {

using test::DeviceCase;

// The plugin, or why the tests skip. A build with nvcc names its plugin file.
const NsMpmBackend* plugin(std::string& why) {
#ifdef NEEDLESIM_MPM_CUDA_PLUGIN_BUILT
  setenv("NEEDLESIM_MPM_CUDA_PLUGIN", NEEDLESIM_MPM_CUDA_PLUGIN_BUILT, 0);  // unless set by the caller
#endif
  const PluginLoad load = loadCudaPlugin();
  if (!load.backend) {
    why = load.problem;
    return nullptr;
  }
  char msg[512] = "";
  if (load.backend->probe(msg, sizeof msg) < 1) {
    why = std::string("no CUDA device: ") + msg;
    return nullptr;
  }
  return load.backend;
}

#define NEEDLESIM_NEED_GPU(backend)              \
  std::string why_;                              \
  const NsMpmBackend* backend = plugin(why_);    \
  if (!backend) GTEST_SKIP() << why_;

struct GpuCase {
  DeviceCase problem;
  int kernel;
};

class GpuAgreement : public ::testing::TestWithParam<GpuCase> {};

TEST_P(GpuAgreement, RigidForceMatchesCpu) {
  NEEDLESIM_NEED_GPU(backend);
  const GpuCase c = GetParam();
  auto cpu = test::deviceProblem(c.problem);
  auto gpu = test::deviceProblem(c.problem);
  gpu->attachDevice(backend, c.kernel);
  const test::Agreement first = test::compareRuns(*cpu, *gpu, 100);
  std::printf("%s, kernel %d: first 100 steps: worst relative force difference %.3g (step %d), %d contact nodes, "
              "|F| up to %.3g N, positions within %.3g m\n",
              c.problem.name, c.kernel, first.worst, first.worstStep, first.maxContactNodes, first.maxForce,
              first.worstPosition);
  EXPECT_GT(first.maxContactNodes, 10);
  EXPECT_LT(first.worst, 1e-6);
  // Steps 100-140 (the tip to the exit face): the force history within 1e-4 of its peak.
  double peak = 0.0;
  const double worst = test::compareHistory(*cpu, *gpu, 40, first.maxForce, peak);
  std::printf("%s, kernel %d: steps 100-140: largest force difference %.3g of the peak %.3g N\n", c.problem.name,
              c.kernel, worst, peak);
  EXPECT_LT(worst, 1e-4);
}

INSTANTIATE_TEST_SUITE_P(
    Cases, GpuAgreement,
    ::testing::Values(GpuCase{DeviceCase{"bspline_musl_conical"}, NSMPM_KERNEL_SORTED},
                      GpuCase{DeviceCase{"bspline_musl_conical_naive"}, NSMPM_KERNEL_NAIVE},
                      GpuCase{DeviceCase{"linear_musl_bevel_gravity", Shape::Linear, Update::MUSL,
                                         RigidBody::Tip::Bevel, true, false, 0.95},
                              NSMPM_KERNEL_SORTED},
                      GpuCase{DeviceCase{"bspline_usl_conical", Shape::BSpline2, Update::USL}, NSMPM_KERNEL_SORTED},
                      GpuCase{DeviceCase{"two_blocks", Shape::BSpline2, Update::MUSL, RigidBody::Tip::Blunt, false,
                                         true},
                              NSMPM_KERNEL_SORTED},
                      GpuCase{DeviceCase{"two_blocks_naive", Shape::BSpline2, Update::MUSL, RigidBody::Tip::Blunt,
                                         false, true},
                              NSMPM_KERNEL_NAIVE}),
    [](const auto& info) { return std::string(info.param.problem.name); });

std::string quickExample(bool cuda) {
  const char* root = std::getenv("NEEDLESIM_SOURCE_DIR");  // the checkout when the binary was built elsewhere
  std::ifstream in(std::string(root && *root ? root : NEEDLESIM_SOURCE_DIR) + "/examples/mpm/quick_needle_block.yaml");
  EXPECT_TRUE(in.good()) << "examples/mpm/quick_needle_block.yaml not found (set NEEDLESIM_SOURCE_DIR)";
  std::stringstream text;
  text << in.rdbuf();
  std::string s = text.str();
  const std::string key = "  mpm:\n";
  const auto at = s.find(key);
  EXPECT_NE(at, std::string::npos);
  s.insert(at + key.size(), std::string("    device: ") + (cuda ? "cuda" : "cpu") + "\n    contact: grid\n    field_interval: 0 s\n");
  const auto fi = s.find("    field_interval: 0.25 s\n");
  if (fi != std::string::npos) s.erase(fi, std::string("    field_interval: 0.25 s\n").size());
  return s;
}

// The quick example through the engine: forces.csv rows (10 ms impulse
// averages) within 1e-6 relative (to |F| or 0.1 % of the peak, whichever is
// larger) over the first 28 rows (~100 steps), all rows within 1e-4 of the peak.
TEST(GpuQuickExample, ForceHistoryMatchesCpu) {
  NEEDLESIM_NEED_GPU(backend);
  (void)backend;
  const MemorySink cpu = runInMemory(scenario::readText(quickExample(false), "quick_cpu.yaml"));
  const MemorySink gpu = runInMemory(scenario::readText(quickExample(true), "quick_gpu.yaml"));
  const auto fc = cpu.tables.at("forces").column("force_total"), fg = gpu.tables.at("forces").column("force_total");
  ASSERT_EQ(fc.size(), fg.size());
  double peak = 0.0;
  for (double f : fc) peak = std::max(peak, std::abs(f));
  ASSERT_GT(peak, 1e-4);
  double early = 0.0, all = 0.0;
  for (std::size_t i = 0; i < fc.size(); ++i) {
    const double d = std::abs(fc[i] - fg[i]);
    if (i < 28) early = std::max(early, d / std::max(std::abs(fc[i]), 1e-3 * peak));
    all = std::max(all, d / peak);
  }
  std::printf("quick example: %zu rows, peak %.4g N; first 28 rows within %.3g relative, all within %.3g of the peak\n",
              fc.size(), peak, early, all);
  EXPECT_LT(early, 1e-6);
  EXPECT_LT(all, 1e-4);
  bool noted = false;
  for (const auto& n : gpu.notes) noted = noted || n.find("ran on the GPU") != std::string::npos;
  EXPECT_TRUE(noted);
}

// Where the plugin is built but no device is present: a clear refusal (exit 2).
TEST(GpuRefusal, NoDeviceIsAnInputError) {
#ifdef NEEDLESIM_MPM_CUDA_PLUGIN_BUILT
  setenv("NEEDLESIM_MPM_CUDA_PLUGIN", NEEDLESIM_MPM_CUDA_PLUGIN_BUILT, 0);
#endif
  const PluginLoad load = loadCudaPlugin();
  if (!load.backend) GTEST_SKIP() << load.problem;
  char msg[512] = "";
  if (load.backend->probe(msg, sizeof msg) > 0) GTEST_SKIP() << "a CUDA device is present: " << msg;
  try {
    runInMemory(scenario::readText(quickExample(true), "quick_gpu.yaml"));
    FAIL() << "ran without a device";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("no usable CUDA device"), std::string::npos) << e.what();
    EXPECT_EQ(e.field(), "model.mpm.device");
  }
}

}  // namespace
}  // namespace needlesim::mpm
