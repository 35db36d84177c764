// Cost of one constitutive evaluation (energy, stress and tangent) per law, 3D
// and plane strain, and of one Prony update: what an FE engine pays per
// integration point and step.
#include <benchmark/benchmark.h>

#include <Eigen/Core>

#include "needlesim/materials/hyperelastic.hpp"
#include "needlesim/materials/viscoelastic.hpp"

using namespace needlesim::materials;

namespace {
Hyperelastic law(int which) {
  Hyperelastic h;
  h.bulk = 2e5;
  switch (which) {
    case 0: h.kind = LawKind::Linear; h.E = 30e3; h.nu = 0.45; break;
    case 1: h.kind = LawKind::NeoHookean; h.C10 = 3.6e3; break;
    case 2: h.kind = LawKind::MooneyRivlin; h.C10 = 2e3; h.C01 = 1e3; break;
    case 3: h.kind = LawKind::Yeoh; h.C10 = 2e3; h.C20 = 1e3; h.C30 = 500; break;
    case 4: h.kind = LawKind::Ogden; h.ogdenMu = {4e3, -1e3}; h.ogdenAlpha = {3.5, -2}; break;
    default: h.kind = LawKind::Fung; h.mu = 5e3; h.gamma = 1.8; break;
  }
  return h;
}
const char* kNames[] = {"linear", "neo-hookean", "mooney-rivlin", "yeoh", "ogden2", "fung"};
}  // namespace

static void BM_Evaluate3D(benchmark::State& st) {
  Hyperelastic h = law(static_cast<int>(st.range(0)));
  Mat3 F;
  F << 1.12, 0.08, -0.05, 0.03, 0.91, 0.11, -0.07, 0.02, 1.04;
  for (auto _ : st) {
    F(0, 0) += 1e-12;
    benchmark::DoNotOptimize(evaluate(h, F, st.range(1) != 0));
  }
  st.SetLabel(std::string(kNames[st.range(0)]) + (st.range(1) ? " +tangent" : " stress only"));
}
BENCHMARK(BM_Evaluate3D)->ArgsProduct({{0, 1, 2, 3, 4, 5}, {0, 1}});

static void BM_EvaluatePlaneStrain(benchmark::State& st) {
  Hyperelastic h = law(static_cast<int>(st.range(0)));
  Mat2 F;
  F << 1.15, 0.1, -0.06, 0.88;
  for (auto _ : st) {
    F(0, 0) += 1e-12;
    benchmark::DoNotOptimize(evaluatePlaneStrain(h, F));
  }
  st.SetLabel(kNames[st.range(0)]);
}
BENCHMARK(BM_EvaluatePlaneStrain)->DenseRange(0, 5);

static void BM_PronyUpdateVoigt6(benchmark::State& st) {
  Prony p;
  p.terms = {{0.3, 0.5}, {0.2, 5.0}, {0.1, 50.0}};
  PronyState<Eigen::Matrix<double, 6, 1>> s;
  Eigen::Matrix<double, 6, 1> Se = Eigen::Matrix<double, 6, 1>::Constant(100.0);
  for (auto _ : st) {
    Se[0] += 1e-3;
    benchmark::DoNotOptimize(pronyUpdate(p, s, Se, 1e-3));
  }
}
BENCHMARK(BM_PronyUpdateVoigt6);

BENCHMARK_MAIN();
