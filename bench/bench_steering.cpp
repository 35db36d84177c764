// Steering models: full 150 mm predictions per second (issue 4 goals per core:
// kinematic >= 100k/s, beam-on-foundation at 1 mm increments >= 1k/s, the whole
// Table 2 energy validation < 1 s).
#include <benchmark/benchmark.h>

#include <numbers>
#include <vector>

#include "needlesim/engines/steering/beam_foundation.hpp"
#include "needlesim/engines/steering/curvature_fit.hpp"
#include "needlesim/engines/steering/energy_model.hpp"
#include "needlesim/engines/steering/kinematic.hpp"
#include "needlesim/engines/steering/table2.hpp"
#include "needlesim/needle/section.hpp"

using namespace needlesim::steering;

static void BM_Kinematic150mm(benchmark::State& st) {
  KinematicParams par{1 / 0.3, 1e-3};
  const Control plan[] = {{0, 0.075}, {std::numbers::pi, 0.075}};  // with a flip halfway
  std::vector<Vec3> out(kinematicSampleCount(par, plan));
  for (auto _ : st) {
    Pose end;
    benchmark::DoNotOptimize(simulateKinematic(par, Pose{}, plan, out, &end));
    benchmark::DoNotOptimize(end.p.data());
  }
  st.SetItemsProcessed(st.iterations());
}
BENCHMARK(BM_Kinematic150mm);

static void BM_KinematicDutyCycled150mm(benchmark::State& st) {
  KinematicParams par{1 / 0.2, 1e-3};
  Control c;
  c.length = 0.15;
  c.duty_cycle = 0.5;
  c.cycle_length = 5e-3;
  const Control plan[] = {c};
  std::vector<Vec3> out(kinematicSampleCount(par, plan));
  for (auto _ : st) benchmark::DoNotOptimize(simulateKinematic(par, Pose{}, plan, out));
  st.SetItemsProcessed(st.iterations());
}
BENCHMARK(BM_KinematicDutyCycled150mm);

static void BM_BeamFoundation150mm_1mm(benchmark::State& st) {
  const double EI = needlesim::needle::Section{50e9, 0.46e-3, 0}.EI();
  BeamFoundationModel m({EI, 9.21e3, -0.8e-3, 5e-8, -2e-3, 1e-3, 0.152});
  for (auto _ : st) {
    m.reset(Pose{});
    for (int i = 0; i < 150; ++i) m.advance();
    benchmark::DoNotOptimize(m.tip().data());
  }
  st.SetItemsProcessed(st.iterations());
}
BENCHMARK(BM_BeamFoundation150mm_1mm)->Unit(benchmark::kMicrosecond);

static void BM_EnergyTable2All12(benchmark::State& st) {
  for (auto _ : st)
    for (const auto& c : table2Cases()) benchmark::DoNotOptimize(runTable2Case(c, "energy"));
  st.SetItemsProcessed(st.iterations());
}
BENCHMARK(BM_EnergyTable2All12)->Unit(benchmark::kMillisecond);

static void BM_CircleFit151(benchmark::State& st) {
  std::vector<Vec3> pts;
  for (int i = 0; i <= 150; ++i) pts.push_back(Vec3(0, -0.3 * (1 - std::cos(i / 300.0)), 0.3 * std::sin(i / 300.0)));
  for (auto _ : st) benchmark::DoNotOptimize(sectionRadii(pts));
  st.SetItemsProcessed(st.iterations());
}
BENCHMARK(BM_CircleFit151);

BENCHMARK_MAIN();
