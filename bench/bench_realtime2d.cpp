// Steps per second of the real-time 2D FE session on one core (seed 003 model):
// the thesis mesh (120 x 80 mm, 21 x 31 = 651 nodes, modal back-end) and a
// 10,000-node mesh (80 x 125 nodes, graded; direct sparse and reduced back-ends), each during
// a steady 3 mm/s insertion with coupled nodes along the shaft. And the thesis scenario's session
// stepped bare and as a steppable session (engines/session.hpp: the step guard, the adapter), as
// the C++ API, needlesim serve and Python step it.
#include <benchmark/benchmark.h>

#include <cmath>
#include <numbers>

#include "needlesim/engines/realtime2d/realtime2d_engine.hpp"
#include "needlesim/engines/realtime2d/session.hpp"
#include "needlesim/engines/session.hpp"
#include "needlesim/scenario/reader.hpp"

using namespace needlesim::realtime2d;

namespace {
SessionConfig config(int nx, int ny, Backend b) {
  SessionConfig c = thesisGelatinConfig(nx, ny, b);
  c.tissue.mesh.grading = nx > 40 ? 3.0 : 1.0;
  return c;
}

void run(benchmark::State& state, int nx, int ny, Backend b) {
  Session s(config(nx, ny, b));
  const double dt = 1e-3, v = 3e-3;
  double depth = 0.0;
  for (int n = 0; n < 10000; ++n) s.step(s.poseAtDepth(depth += v * dt), dt);  // 30 mm in
  for (auto _ : state) {
    depth += v * dt;
    if (depth > 0.06) depth = 0.03;  // stay in the insertion phase
    benchmark::DoNotOptimize(s.step(s.poseAtDepth(depth), dt).axial_force);
  }
  state.counters["steps_per_s"] = benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
  state.counters["nodes"] = s.mesh().nodeCount();
  state.counters["coupled"] = s.last().coupled;
}
}  // namespace

static void BM_ThesisMesh651_Modal(benchmark::State& st) { run(st, 21, 31, Backend::Modal); }
static void BM_ThesisMesh651_Direct(benchmark::State& st) { run(st, 21, 31, Backend::Direct); }
static void BM_Mesh10000_Direct(benchmark::State& st) { run(st, 80, 125, Backend::Direct); }
static void BM_Mesh10000_Reduced(benchmark::State& st) { run(st, 80, 125, Backend::Reduced); }
BENCHMARK(BM_ThesisMesh651_Modal)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_ThesisMesh651_Direct)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_Mesh10000_Direct)->Unit(benchmark::kMicrosecond)->Iterations(300);
BENCHMARK(BM_Mesh10000_Reduced)->Unit(benchmark::kMicrosecond);

namespace {
const needlesim::Scenario& thesisScenario() {
  static const needlesim::Scenario sc = needlesim::scenario::readFile(NEEDLESIM_EXAMPLES_DIR "realtime2d/thesis_gelatin_18G_3mms.yaml");
  return sc;
}

// The depth of 1 ms steps at 3 mm/s, in to 60 mm, out to 30 mm and in again (a jump back
// would be refused by the step guard), after 30 mm of warm-up.
struct Stroke {
  double depth = 0.0, velocity = 3e-3;
  double next() {
    if ((velocity > 0.0 && depth > 0.06) || (velocity < 0.0 && depth < 0.03)) velocity = -velocity;
    return depth += velocity * 1e-3;
  }
};
}  // namespace

static void BM_ThesisScenario_EngineSession(benchmark::State& state) {
  Session s(needlesim::engines::realtime2dConfig(thesisScenario()));
  Stroke stroke;
  for (int n = 0; n < 10000; ++n) s.step(s.poseAtDepth(stroke.next()), 1e-3);
  for (auto _ : state) benchmark::DoNotOptimize(s.step(s.poseAtDepth(stroke.next()), 1e-3).axial_force);
}

static void BM_ThesisScenario_SteppableSession(benchmark::State& state) {
  const auto s = needlesim::engines::openSession(thesisScenario());
  Stroke stroke;
  for (int n = 0; n < 10000; ++n) s->step({stroke.next()}, 1e-3);
  for (auto _ : state) benchmark::DoNotOptimize(s->step({stroke.next()}, 1e-3).axial_force);
}
// The step guard alone (finite arguments, axes, reach, travel), a step inside the tissue.
static void BM_SessionGuard(benchmark::State& state) {
  const needlesim::Scenario& sc = thesisScenario();
  const needlesim::engines::SessionGuard guard(sc, needlesim::engines::realtime2dStepPlan(sc),
                                               {.lateral = true, .rotation = true, .roll = true});
  needlesim::engines::SessionCommand c{0.03};
  unsigned k = 0;
  for (auto _ : state) {
    c.depth = 0.03 + 1e-9 * (++k & 1023u);
    benchmark::DoNotOptimize(c);
    guard.check(c, 1e-3, 0.03);
  }
}
// The same 20,000 steps (in 30 -> 60 mm, out to 30 mm) for both.
BENCHMARK(BM_ThesisScenario_EngineSession)->Unit(benchmark::kMicrosecond)->Iterations(20000);
BENCHMARK(BM_ThesisScenario_SteppableSession)->Unit(benchmark::kMicrosecond)->Iterations(20000);
BENCHMARK(BM_SessionGuard);

BENCHMARK_MAIN();
