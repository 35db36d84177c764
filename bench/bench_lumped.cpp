// Lumped force model (seed 003 section 3.2): force evaluations per second,
// the rate a haptic loop or a planner can call it at.
#include <benchmark/benchmark.h>

#include "needlesim/forces/lumped_model.hpp"
#include "needlesim/insertion/motion_profile.hpp"
#include "needlesim/scenario/reader.hpp"

using namespace needlesim;

static void BM_LumpedStep(benchmark::State& state) {
  Scenario sc = scenario::readFile(std::string(NEEDLESIM_EXAMPLES_DIR) + "layered_skin_fat_muscle.yaml");
  forces::LumpedForceModel model(sc.tissue, sc.needle, sc.insertion.entry_angle);
  MotionProfile motion(sc.insertion);
  const double dt = 1e-3;
  double t = 0.0, sum = 0.0;
  for (auto _ : state) {
    auto m = motion.at(t);
    sum += model.step(m.depth, m.velocity, dt).total();
    t += dt;
    if (t > motion.duration()) {
      t = 0.0;
      model.reset();
    }
  }
  benchmark::DoNotOptimize(sum);
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_LumpedStep);

// A whole default insertion (0.07 m in, 5 s pause, out) at 1 kHz: 53 k steps.
static void BM_LumpedDefaultScenario(benchmark::State& state) {
  Scenario sc = scenario::defaultScenario();
  MotionProfile motion(sc.insertion);
  const double dt = sc.model.time_step;
  for (auto _ : state) {
    forces::LumpedForceModel model(sc.tissue, sc.needle, sc.insertion.entry_angle);
    double peak = 0.0;
    for (double t = 0.0; t <= motion.duration(); t += dt) {
      auto m = motion.at(t);
      peak = std::max(peak, model.step(m.depth, m.velocity, dt).total());
    }
    benchmark::DoNotOptimize(peak);
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_LumpedDefaultScenario)->Unit(benchmark::kMillisecond);

BENCHMARK_MAIN();
