// Explicit FE (engines/explicit): element updates per second (internal force,
// hourglass, stable step, lumped-mass central-difference update) for 2D
// plane-strain quad4 and 3D hex8 blocks with the neo-Hookean fast path and,
// for comparison, a law evaluated through materials::evaluate (Mooney-Rivlin); tet4 with and
// without the average nodal pressure.
#include <benchmark/benchmark.h>

#include "needlesim/engines/explicit/solver.hpp"

using namespace needlesim;
using namespace needlesim::explicit_fe;

namespace {
materials::MaterialSpec law(const std::string& name) {
  materials::MaterialSpec s;
  s.law = name;
  if (name == "neo-hookean") s.params = {{"C10", 3.6e3}, {"nu", 0.495}};
  else s.params = {{"C10", 2e3}, {"C01", 1.6e3}, {"nu", 0.495}};
  return s;
}
std::vector<double> line(int n) {
  std::vector<double> x;
  for (int i = 0; i <= n; ++i) x.push_back(0.02 * i / n);
  return x;
}
void run(benchmark::State& state, Mesh m, const std::string& lawName, bool nodalPressure = true) {
  SolverOptions o;
  o.nodalPressure = nodalPressure;
  ExplicitSolver s(m, {Material::fromSpec(law(lawName))}, o);
  const int d = m.dim;
  for (int n = 0; n < m.nodes(); ++n) s.velocityMutable()[n * d + 1] = 1e-3 * m.coord(n, 0);
  for (auto _ : state) s.step();
  state.SetItemsProcessed(state.iterations() * m.elements());
  state.counters["elements"] = m.elements();
}
}  // namespace

static void BM_ExplicitQuad4(benchmark::State& st) {
  int n = static_cast<int>(st.range(0));
  run(st, structuredBlock(line(n), line(n), ElementType::Quad4), st.range(1) ? "mooney-rivlin" : "neo-hookean");
}
BENCHMARK(BM_ExplicitQuad4)->Args({100, 0})->Args({300, 0})->Args({300, 1})->Unit(benchmark::kMillisecond);

static void BM_ExplicitHex8(benchmark::State& st) {
  int n = static_cast<int>(st.range(0));
  run(st, structuredBlock(line(n), line(n), line(n), ElementType::Hex8), st.range(1) ? "mooney-rivlin" : "neo-hookean");
}
BENCHMARK(BM_ExplicitHex8)->Args({20, 0})->Args({40, 0})->Args({40, 1})->Unit(benchmark::kMillisecond);

// tet4 with and without the average nodal pressure (nodal_pressure.cpp)
static void BM_ExplicitTet4(benchmark::State& st) {
  int n = static_cast<int>(st.range(0));
  run(st, structuredBlock(line(n), line(n), line(n), ElementType::Tet4), "neo-hookean", st.range(1) != 0);
}
BENCHMARK(BM_ExplicitTet4)->Args({20, 0})->Args({20, 1})->Unit(benchmark::kMillisecond);

BENCHMARK_MAIN();
