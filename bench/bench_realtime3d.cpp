// Steps per second of the real-time 3D session on one core (engines/realtime3d): the thesis
// gelatin and 18 G bevel needle (seed 003 section 5.1) in an 80 x 80 x 80 mm tetrahedral block
// graded towards the needle path, 41 x 16 x 16 = 10,496 nodes (61,500 tets), reduced back-end.
// The session is first warmed to 50 mm of insertion (needle 50 mm in); the timed steps then
// move the needle 50 -> 55 -> 50 mm at 3 mm/s (insertion and retraction, force out each step).
#include <benchmark/benchmark.h>

#include <cmath>

#include "needlesim/engines/realtime3d/session.hpp"

using namespace needlesim::realtime3d;

namespace {
void run(benchmark::State& state, int nx, int nl, Backend b) {
  Eigen::setNbThreads(1);  // one core (a step has no matrix-matrix product, but set-up would use OpenMP)
  SessionConfig c = gelatinBlockConfig(nx, nl, b);
  Session s(c);
  const double dt = 1e-3;
  double depth = -1e-3;
  while (depth < 0.05) s.step(s.poseAtDepth(depth += 10e-3 * dt), dt);  // warm: 10 mm/s to 50 mm
  double dir = 1.0;
  for (auto _ : state) {
    depth += dir * 3e-3 * dt;
    if (depth > 0.055 || depth < 0.05) dir = -dir;
    benchmark::DoNotOptimize(s.step(s.poseAtDepth(depth), dt).axial_force);
  }
  state.counters["steps_per_s"] = benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
  state.counters["nodes"] = s.mesh().nodes();
  state.counters["tets"] = s.mesh().elements();
  state.counters["coupled"] = s.last().coupled;
  state.counters["path_dofs"] = s.tissue().dynamics().pathDofs();
}
}  // namespace

static void BM_Block10496_Reduced(benchmark::State& st) { run(st, 41, 16, Backend::Reduced); }
BENCHMARK(BM_Block10496_Reduced)->Unit(benchmark::kMicrosecond)->MinTime(2.0);

BENCHMARK_MAIN();
