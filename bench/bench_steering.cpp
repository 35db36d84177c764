// Steering models: full 150 mm predictions per second (issue 4 goals per core:
// kinematic >= 100k/s, beam-on-foundation at 1 mm increments >= 1k/s, the whole
// Table 2 energy validation < 1 s).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>
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

// the default energy frame (path-window, EnergyParams{}.frame) with the section 5.2 inputs
static void BM_EnergyTable2All12(benchmark::State& st) {
  for (auto _ : st)
    for (const auto& c : table2Cases()) benchmark::DoNotOptimize(runTable2Case(c, "energy"));
  st.SetItemsProcessed(st.iterations());
}
BENCHMARK(BM_EnergyTable2All12)->Unit(benchmark::kMillisecond);

// the literal eq 45 frame, for comparison
static void BM_EnergyEntryFrameTable2All12(benchmark::State& st) {
  for (auto _ : st)
    for (const auto& c : table2Cases()) benchmark::DoNotOptimize(runTable2Case(c, "energy-entry"));
  st.SetItemsProcessed(st.iterations());
}
BENCHMARK(BM_EnergyEntryFrameTable2All12)->Unit(benchmark::kMillisecond);

// one energy-model prediction (gel C, 0.54 mm, section 5.2 inputs, default frame)
static void BM_Energy150mm(benchmark::State& st) {
  const Table2Case& c = table2Cases()[8];
  for (auto _ : st) benchmark::DoNotOptimize(runTable2Case(c, "energy"));
  st.SetItemsProcessed(st.iterations());
}
BENCHMARK(BM_Energy150mm)->Unit(benchmark::kMicrosecond);

// leave-two-out calibration of the energy model: 4 gels x 3 calibration needles, each a
// bisection on beta/alpha plus two predictions (docs/validation/steering.md)
static void BM_EnergyTable2CrossValidation(benchmark::State& st) {
  for (auto _ : st)
    for (int cal = 0; cal < 3; ++cal) benchmark::DoNotOptimize(table2CrossValidation("energy", cal));
  st.SetItemsProcessed(st.iterations());
}
BENCHMARK(BM_EnergyTable2CrossValidation)->Unit(benchmark::kMillisecond);

static void BM_CircleFit151(benchmark::State& st) {
  std::vector<Vec3> pts;
  for (int i = 0; i <= 150; ++i) pts.push_back(Vec3(0, -0.3 * (1 - std::cos(i / 300.0)), 0.3 * std::sin(i / 300.0)));
  for (auto _ : st) benchmark::DoNotOptimize(sectionRadii(pts));
  st.SetItemsProcessed(st.iterations());
}
BENCHMARK(BM_CircleFit151);

// `bench_steering --table2` prints the Table 2 validation tables of docs/validation/steering.md
// (section 5.2 inputs per model, then the per-gel calibration and leave-two-out predictions)
// instead of timing.
static void printTable2() {
  const char* models[] = {"energy", "energy-entry", "energy-window-tip-beta", "beam-foundation", "beam-foundation-edges"};
  std::printf("gel d_mm rho_exp_mm defl_exp_mm");
  for (const char* m : models) std::printf(" %s:rho_mm,dev_%%,defl_mm", m);
  std::printf("\n");
  for (const auto& c : table2Cases()) {
    std::printf("%s %.2f %.1f", c.gel, c.diameter * 1e3, c.rho_exp * 1e3);
    bool first = true;
    for (const char* m : models) {
      const Table2Row r = runTable2Case(c, m);
      if (first) std::printf(" %.1f", r.deflection_exp * 1e3);
      first = false;
      std::printf(" %.1f,%+.0f,%.1f", r.rho_pred * 1e3, 100 * (r.rho_pred / c.rho_exp - 1), r.deflection_pred * 1e3);
    }
    std::printf("\n");
  }
  for (const char* m : {"energy", "beam-foundation", "kinematic", "radius-proportional"})
    for (int cal = 0; cal < 3; ++cal) {
      double mean = 0, worst = 0;
      for (const auto& pr : table2CrossValidation(m, cal)) {
        const Table2Case& c = table2Cases()[pr.case_index];
        std::printf("%s calibrated on %.2f mm: %s %.2f mm parameter %.4g rho %.1f mm (exp %.1f) error %+.1f %%\n", m,
                    table2Cases()[pr.calibration_case].diameter * 1e3, c.gel, c.diameter * 1e3, pr.beta_ratio,
                    pr.rho_pred * 1e3, c.rho_exp * 1e3, 100 * pr.error);
        mean += std::abs(pr.error) / 8;
        worst = std::max(worst, std::abs(pr.error));
      }
      std::printf("%s calibrated on needle %d: mean |error| %.1f %%, max %.1f %%\n", m, cal, 100 * mean, 100 * worst);
    }
}

int main(int argc, char** argv) {
  for (int i = 1; i < argc; ++i)
    if (std::string(argv[i]) == "--table2") {
      printTable2();
      return 0;
    }
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
