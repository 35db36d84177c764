// MPM throughput: particle-steps per second with frictional contact, ~50k
// particles (a needle into a Fung-Demiray block, quadratic B-spline or linear
// shapes, MUSL), on 1 and 2 threads; the same needle problem in a block of
// 1,008,000 points (--large). Figures: docs/performance.md.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <numbers>
#include <vector>

#include "needlesim/engines/mpm/cuda/plugin_loader.hpp"
#include "needlesim/engines/mpm/mpm_solver.hpp"

using namespace needlesim::mpm;

namespace {

// The GPU back-end of --device cuda (null: the CPU) and its P2G kernel.
struct Device {
  const NsMpmBackend* backend = nullptr;
  int kernel = NSMPM_KERNEL_SORTED;
};

// A bevel needle 2 mm into a Fung-Demiray block of length x width x height
// (needle along x, centred in y and z), 0.4 mm particles, 0.8 mm grid, after
// `warmup` steps (on the GPU back-end of `device` when it has one). The default 22 x 12 x 12 mm block: 49,500 particles; the
// large one, 28 x 48 x 48 mm: 1,008,000.
MpmSolver makeNeedleProblem(Shape shape, Update update, int threads, const Vec3& size = Vec3(22e-3, 12e-3, 12e-3),
                            int warmup = 20, Device device = {}) {
  const double h = 0.8e-3, dp = 0.4e-3;
  const double hy = size.y() / 2, hz = size.z() / 2;
  MpmConfig cfg;
  cfg.h = h;
  cfg.shape = shape;
  cfg.update = update;
  cfg.threads = threads;
  cfg.origin = Vec3(-4 * h, -hy - 3 * h, -hz - 3 * h);
  cfg.cells = {static_cast<int>(size.x() / h) + 8, static_cast<int>(size.y() / h) + 7,
               static_cast<int>(size.z() / h) + 7};
  cfg.boxLo = Vec3(0, -hy, -hz);
  cfg.boxHi = Vec3(size.x(), hy, hz);
  cfg.faces = {FaceBC::Free, FaceBC::Fixed, FaceBC::Roller, FaceBC::Roller, FaceBC::Roller, FaceBC::Roller};
  cfg.massScaling = 1e4;
  MpmSolver s(cfg);
  MpmMaterial m;
  m.law.kind = needlesim::materials::LawKind::Fung;
  m.law.mu = 5e3;
  m.law.gamma = 2.0;
  m.law.bulk = 2.5e5;
  m.density = 1000;
  s.addMaterial(m);
  s.addBlock(cfg.boxLo, cfg.boxHi, dp, 0, 0);
  RigidBody n;
  n.kind = RigidBody::Kind::Needle;
  n.tip = RigidBody::Tip::Bevel;
  n.radius = 0.44e-3;
  n.tipAngle = 20 * std::numbers::pi / 180;
  n.bevelSide = -Vec3::UnitY();     // the sharp point on the +y wall, the axis on y = 0
  n.point = Vec3(2e-3, 0.44e-3, 0);  // tip 2 mm inside: frictional contact along the shaft
  n.velocity = Vec3(6e-3, 0, 0);
  n.friction = 0.255;
  s.addRigid(n);
  s.finalize();
  if (device.backend) s.attachDevice(device.backend, device.kernel);
  for (int i = 0; i < warmup; ++i) s.step();
  return s;
}

void BM_MpmNeedle(benchmark::State& st) {
  const Shape shape = st.range(0) ? Shape::BSpline2 : Shape::Linear;
  const Update update = st.range(1) ? Update::MUSL : Update::USL;
  MpmSolver s = makeNeedleProblem(shape, update, static_cast<int>(st.range(2)));
  for (auto _ : st) {
    s.step();
    s.rigid(0).point += s.rigid(0).velocity * s.lastReport().dt;
  }
  st.counters["particles"] = static_cast<double>(s.size());
  st.counters["particle_steps_per_s"] =
      benchmark::Counter(static_cast<double>(s.size()), benchmark::Counter::kIsIterationInvariantRate);
  st.counters["contact_nodes"] = s.rigidForce(0).contactNodes;
}

// Two deformable blocks (two velocity fields, frictional two-body contact
// between them, mu 0.3: the default penalty contact of penalty_contact.hpp;
// the velocity contact of eqs 14-21 before it) pressed together while
// sliding: 2 x 25,600 = 51,200 points.
MpmSolver makeTwoBlockProblem(Shape shape, Update update, int threads) {
  const double h = 0.8e-3, dp = 0.4e-3, a = 16e-3, b = 6.4e-3;
  MpmConfig cfg;
  cfg.h = h;
  cfg.shape = shape;
  cfg.update = update;
  cfg.threads = threads;
  cfg.bodies = 2;
  cfg.friction = 0.3;
  cfg.origin = Vec3(-4 * h, -4 * h, -4 * h);
  cfg.cells = {static_cast<int>(2 * b / h) + 12, static_cast<int>(a / h) + 8, static_cast<int>(a / h) + 8};
  cfg.massScaling = 1e4;
  MpmSolver s(cfg);
  MpmMaterial m;
  m.law.kind = needlesim::materials::LawKind::Fung;
  m.law.mu = 5e3;
  m.law.gamma = 2.0;
  m.law.bulk = 2.5e5;
  m.density = 1000;
  s.addMaterial(m);
  s.addBlock(Vec3(0, 0, 0), Vec3(b, a, a), dp, 0, 0, Vec3(0.002, 0.001, 0));
  s.addBlock(Vec3(b + 0.1e-3, 0, 0), Vec3(2 * b + 0.1e-3, a, a), dp, 0, 1, Vec3(-0.002, -0.001, 0));
  s.finalize();
  for (int i = 0; i < 40; ++i) s.step();
  return s;
}

void BM_MpmTwoBlocks(benchmark::State& st) {
  const Shape shape = st.range(0) ? Shape::BSpline2 : Shape::Linear;
  const Update update = st.range(1) ? Update::MUSL : Update::USL;
  MpmSolver s = makeTwoBlockProblem(shape, update, static_cast<int>(st.range(2)));
  for (auto _ : st) s.step();
  st.counters["particles"] = static_cast<double>(s.size());
  st.counters["particle_steps_per_s"] =
      benchmark::Counter(static_cast<double>(s.size()), benchmark::Counter::kIsIterationInvariantRate);
}

// --phases: the mean wall time of each phase of a step (ms), its share of the
// step, the process CPU time over the wall time in it (threads busy or
// spinning: about T in a parallel phase, 1 in a serial one unless idle
// threads spin at its start) and, for the particle passes, the busiest
// thread's work time over the mean (MpmSolver::threadBusy).
void printPhases(const MpmSolver& s, int steps) {
  const auto& wall = s.phaseTimes();
  const auto& cpu = s.phaseCpuTimes();
  double total = 0;
  for (double w : wall) total += w;
  std::printf("phases (%d threads, mean per step):\n%-20s %9s %7s %9s %10s\n", s.threads(), "phase", "wall ms", "share",
              "cpu/wall", "work imb.");
  for (int k = 0; k < MpmSolver::kPhases; ++k) {
    const double w = wall[static_cast<std::size_t>(k)], c = cpu[static_cast<std::size_t>(k)];
    if (w == 0) continue;
    std::printf("%-20s %9.3f %6.1f%% %9.2f", MpmSolver::phaseName(k), 1e3 * w / steps, 100 * w / total, c / w);
    // the particle passes: the busiest thread's work time over the mean (barrier waits left out)
    const std::vector<double> busy = s.threadBusy(static_cast<MpmSolver::Phase>(k));
    double most = 0, sum = 0;
    for (double b : busy) {
      most = std::max(most, b);
      sum += b;
    }
    if (sum > 0) std::printf(" %10.3f", most * static_cast<double>(busy.size()) / sum);
    std::printf("\n");
  }
  std::printf("%-20s %9.3f\n", "step (sum)", 1e3 * total / steps);
}

}  // namespace

BENCHMARK(BM_MpmTwoBlocks)
    ->ArgNames({"bspline", "musl", "threads"})
    ->Args({1, 1, 1})
    ->Args({1, 1, 2})
    ->Args({0, 1, 1})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// args: B-spline (1) / linear (0), MUSL (1) / USL (0), threads
BENCHMARK(BM_MpmNeedle)
    ->ArgNames({"bspline", "musl", "threads"})
    ->Args({1, 1, 1})
    ->Args({1, 1, 2})
    ->Args({1, 0, 1})
    ->Args({1, 0, 2})
    ->Args({0, 1, 1})
    ->Args({0, 1, 2})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// --device cuda: the plugin into `device`; false (with the reason on stderr) when it cannot run.
bool attachCuda(Device& device, bool twoBlocks) {
  const needlesim::mpm::PluginLoad load = needlesim::mpm::loadCudaPlugin();
  char msg[512] = "";
  if (!load.backend || load.backend->probe(msg, sizeof msg) < 1) {
    std::fprintf(stderr, "bench_mpm: --device cuda: %s\n", load.backend ? msg : load.problem.c_str());
    return false;
  }
  if (twoBlocks) {
    std::fprintf(stderr, "bench_mpm: --device cuda: the two-block problem (two bodies) is CPU-only\n");
    return false;
  }
  std::printf("device: %s, %s kernel\n", msg, device.kernel == NSMPM_KERNEL_NAIVE ? "naive" : "sorted");
  device.backend = load.backend;
  return true;
}

// `bench_mpm --steps N [--linear] [--usl] [--two-blocks | --large] [--threads T]
// [--scale S] [--device cuda [--kernel naive]] [--phases]`: N
// steps of the problem (1 thread unless told) without the benchmark harness, for instruction
// counts under `valgrind --tool=callgrind` (--separate-threads=yes: the work of each thread)
// and the thread scaling (scripts/mpm_scaling.sh); prints the fastest and the median step wall
// time and the scatter's block colouring (docs/performance.md). --large: the needle in a
// 28 x 48 x 48 mm block, 1,008,000 points (~300 MB), after 5 warm-up steps. --scale S: the
// needle problem's block edges times S (4.4: 4.2 M points). --device cuda: the steps on the
// CUDA plugin (docs/architecture.md "MPM on the GPU"), its sorted or naive P2G kernel.
// --phases: the mean wall and CPU time of each phase of a step (MpmSolver::phaseTimes).
int main(int argc, char** argv) {
  int steps = -1;
  Shape shape = Shape::BSpline2;
  Update update = Update::MUSL;
  bool twoBlocks = false, large = false;
  int threads = 1;
  double scale = 1.0;
  Device device;
  bool cuda = false;
  bool phases = false;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--steps" && i + 1 < argc) steps = std::atoi(argv[++i]);
    if (a == "--linear") shape = Shape::Linear;
    if (a == "--usl") update = Update::USL;
    if (a == "--two-blocks") twoBlocks = true;
    if (a == "--large") large = true;
    if (a == "--threads" && i + 1 < argc) threads = std::atoi(argv[++i]);
    if (a == "--scale" && i + 1 < argc) scale = std::atof(argv[++i]);
    if (a == "--device" && i + 1 < argc) cuda = std::string(argv[++i]) == "cuda";
    if (a == "--kernel" && i + 1 < argc) device.kernel = std::string(argv[++i]) == "naive" ? NSMPM_KERNEL_NAIVE : NSMPM_KERNEL_SORTED;
    if (a == "--phases") phases = true;
  }
  if (cuda && !attachCuda(device, twoBlocks)) return 2;
  if (steps >= 0) {
    MpmSolver s = twoBlocks ? makeTwoBlockProblem(shape, update, threads)
                  : large   ? makeNeedleProblem(shape, update, threads, Vec3(28e-3, 48e-3, 48e-3), 5, device)
                            : makeNeedleProblem(shape, update, threads, scale * Vec3(22e-3, 12e-3, 12e-3), 20,
                                                device);
    // Wall time of each step: the fastest and the median (on a shared machine
    // the fastest steps are those that found the cores free).
    std::vector<double> ms;
    s.resetPhaseTimes();
    for (int i = 0; i < steps; ++i) {
      const auto t0 = std::chrono::steady_clock::now();
      s.step();
      ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
      if (!twoBlocks) s.rigid(0).point += s.rigid(0).velocity * s.lastReport().dt;
    }
    std::printf("%zu particles, %d steps, %d threads, kinetic energy %.12e J", s.size(), steps, s.threads(),
                s.lastReport().kinetic);
    if (!twoBlocks) std::printf(", contact nodes %d, force %.12e N", s.rigidForce(0).contactNodes, s.rigidForce(0).total.x());
    std::printf("\n");
    const MpmSolver::ScatterPlan plan = s.scatterPlan(s.threads());
    std::printf("scatter: %zu blocks in %d colours (%d barriers per scatter), %d of %d threads with points, "
                "imbalance %.3f (scatter speed-up <= %.2f), %lld sorts by block\n",
                plan.blocks, plan.colours, plan.colours - 1, plan.busyThreads, s.threads(), plan.imbalance,
                s.threads() / plan.imbalance, plan.sorts);
    if (!ms.empty()) {
      std::sort(ms.begin(), ms.end());
      const double np = static_cast<double>(s.size());
      std::printf("step wall time: fastest %.3f ms (%.2f M particle-steps/s), median %.3f ms (%.2f M/s)\n", ms.front(),
                  np / ms.front() * 1e-3, ms[ms.size() / 2], np / ms[ms.size() / 2] * 1e-3);
      // the spread: deciles of the step time (ms)
      std::printf("deciles (ms):");
      for (int d = 1; d <= 9; ++d) std::printf(" %.2f", ms[ms.size() * static_cast<std::size_t>(d) / 10]);
      std::printf("\n");
    }
    if (phases && steps > 0) printPhases(s, steps);
    return 0;
  }
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
