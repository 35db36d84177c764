// Cohesive interface (engines/explicit/cohesive*): pair updates per second of the
// 3D quadrilateral interface (mid-surface normals, traction law, forces on both lips)
// and of the 2D line interface, on a seam half opened (every pair in the softening
// branch), and the whole explicit step of a hex block with and without the seam.
#include <benchmark/benchmark.h>

#include "needlesim/engines/explicit/cohesive.hpp"
#include "needlesim/engines/explicit/solver.hpp"

using namespace needlesim;
using namespace needlesim::explicit_fe;

namespace {
std::vector<double> line(int n, double a = 0.0, double b = 0.02) {
  std::vector<double> x;
  for (int i = 0; i <= n; ++i) x.push_back(a + (b - a) * i / n);
  return x;
}
CohesiveLaw law() {
  CohesiveLaw l;
  l.stiffness = 1e9;
  l.strength = 1e4;
  l.energy = 5.0;
  return l;
}
// opening 3 delta_0 on every pair (upper lip moved along y), a little shear along x
void openSeam(const std::vector<std::pair<int, int>>& pairs, int dim, std::vector<double>& u) {
  for (auto [a, b] : pairs) {
    (void)a;
    u[b * dim + 1] = 3e-5;
    u[b * dim] = 1e-5;
  }
}
}  // namespace

static void BM_CohesiveQuads3D(benchmark::State& st) {
  const int n = static_cast<int>(st.range(0));
  Mesh m = structuredBlock(line(n), line(2, -0.01, 0.01), line(n), ElementType::Hex8);
  auto pairs = splitSeam(m, 0.0, -1.0, 1.0, 1.0);
  auto c = CohesiveInterface::surface3D(m, pairs, {law()}, Eigen::Vector3d::UnitY(), Eigen::Vector3d::UnitX());
  std::vector<double> u(m.X.size(), 0.0), f(m.X.size(), 0.0);
  openSeam(pairs, 3, u);
  for (auto _ : st) {
    c.addForces(m.X, u, f);
    benchmark::DoNotOptimize(f.data());
  }
  st.SetItemsProcessed(st.iterations() * c.pairs());
  st.counters["pairs"] = c.pairs();
}
BENCHMARK(BM_CohesiveQuads3D)->Arg(100)->Arg(300)->Unit(benchmark::kMicrosecond);

static void BM_CohesiveLines2D(benchmark::State& st) {
  const int n = static_cast<int>(st.range(0));
  Mesh m = structuredBlock(line(n), line(2, -0.01, 0.01), ElementType::Quad4);
  auto pairs = splitSeam(m, 0.0, -1.0, 1.0);
  CohesiveInterface c(m.X, pairs, {law()});
  std::vector<double> u(m.X.size(), 0.0), f(m.X.size(), 0.0);
  openSeam(pairs, 2, u);
  for (auto _ : st) {
    c.addForces(m.X, u, f);
    benchmark::DoNotOptimize(f.data());
  }
  st.SetItemsProcessed(st.iterations() * c.pairs());
}
BENCHMARK(BM_CohesiveLines2D)->Arg(10000)->Unit(benchmark::kMicrosecond);

// Whole explicit step, 40 x 40 x 40 hex block split at mid-height: 1681 seam pairs beside 64k elements.
static void BM_HexStepWithSeam(benchmark::State& st) {
  const int n = 40;
  Mesh m = structuredBlock(line(n), line(n, -0.01, 0.01), line(n), ElementType::Hex8);
  std::vector<std::pair<int, int>> pairs;
  if (st.range(0)) pairs = splitSeam(m, 0.0, -1.0, 1.0, 1.0);
  materials::MaterialSpec ms;
  ms.law = "neo-hookean";
  ms.params = {{"C10", 3.6e3}, {"nu", 0.495}};
  ExplicitSolver s(m, {Material::fromSpec(ms)});
  if (st.range(0))
    s.setCohesive(CohesiveInterface::surface3D(m, pairs, {law()}, Eigen::Vector3d::UnitY(), Eigen::Vector3d::UnitX()));
  for (int k = 0; k < m.nodes(); ++k) s.velocityMutable()[3 * k + 1] = 1e-3 * m.coord(k, 1);
  for (auto _ : st) s.step();
  st.SetItemsProcessed(st.iterations() * m.elements());
}
BENCHMARK(BM_HexStepWithSeam)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

BENCHMARK_MAIN();
