// Steps per second of the real-time 3D session on one core (engines/realtime3d): the thesis
// gelatin and 18 G bevel needle (seed 003 section 5.1) in an 80 x 80 x 80 mm tetrahedral block
// graded towards the needle path, 41 x 16 x 16 = 10,496 nodes (61,500 tets), reduced back-end.
// The session is first warmed to 50 mm of insertion (needle 50 mm in); the timed steps then
// move the needle 50 -> 55 -> 50 mm at 3 mm/s (insertion and retraction, force out each step);
// the _Spacing2mm variant couples at path points 2 mm apart instead of 1 mm.
// The field benchmarks time the viewer's field of needlesim serve on the same warmed block: the
// snapshot the physics thread copies every 16 steps, and the full displacement a viewer thread
// rebuilds from it. The set-up benchmarks time building the session (one iteration each) at
// 10,496 and 41 x 35 x 35 = 50,225 nodes; the 50,225-node block also has a step benchmark.
// The prostate benchmarks time examples/anatomy/prostate_tumour_realtime3d.yaml's gland (Gmsh's
// tets, read and meshed once outside the timing): its set-up, and a step with the needle 20 mm in
// moving 20 -> 22 -> 20 mm at 3 mm/s.
#include <benchmark/benchmark.h>

#include <cmath>

#include "needlesim/engines/realtime3d/realtime3d_engine.hpp"
#include "needlesim/engines/realtime3d/session.hpp"
#include "needlesim/scenario/reader.hpp"

using namespace needlesim::realtime3d;

namespace {
void run(benchmark::State& state, int nx, int nl, Backend b, double spacing = 1e-3) {
  Eigen::setNbThreads(1);  // one core (a step has no matrix-matrix product, but set-up would use OpenMP)
  SessionConfig c = gelatinBlockConfig(nx, nl, b);
  c.tissue.coupling_spacing = spacing;
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

// Set-up of the session on the gelatin block with nx x nl x nl nodes, reduced back-end: mesh,
// assembly, the factorisation of the stiffness, the lowest modes and the path flexibility.
void setup(benchmark::State& state, int nx, int nl) {
  Eigen::setNbThreads(1);
  int nodes = 0;
  for (auto _ : state) {
    const Session s(gelatinBlockConfig(nx, nl, Backend::Reduced));
    nodes = s.mesh().nodes();
    benchmark::DoNotOptimize(nodes);
  }
  state.counters["nodes"] = nodes;
}

// The 10,496-node block warmed to 50 mm as above, built once for the field benchmarks.
Session& warmedBlock() {
  static Session* s = [] {
    Eigen::setNbThreads(1);
    auto* block = new Session(gelatinBlockConfig(41, 16, Backend::Reduced));
    double depth = -1e-3;
    while (depth < 0.05) block->step(block->poseAtDepth(depth += 10e-3 * 1e-3), 1e-3);
    return block;
  }();
  return *s;
}

void fieldSnapshot(benchmark::State& state) {
  const Session& s = warmedBlock();
  needlesim::realtime::DisplacementState saved;
  for (auto _ : state) {
    s.saveDisplacement(saved);
    benchmark::DoNotOptimize(saved.coordinates.data());
  }
  state.counters["modes"] = static_cast<double>(saved.coordinates.size());
  state.counters["path_loads"] = static_cast<double>(saved.residual.size());
}

void fieldFromSnapshot(benchmark::State& state) {
  const Session& s = warmedBlock();
  needlesim::realtime::DisplacementState saved;
  s.saveDisplacement(saved);
  Eigen::VectorXd u;
  for (auto _ : state) {
    s.displacementFrom(saved, u);
    benchmark::DoNotOptimize(u.data());
  }
  state.counters["dofs"] = static_cast<double>(u.size());
}
const SessionConfig& prostateConfig() {
  static const SessionConfig c = needlesim::engines::realtime3dConfig(
      needlesim::scenario::readFile(NEEDLESIM_EXAMPLES_DIR "anatomy/prostate_tumour_realtime3d.yaml"));
  return c;
}

void prostateSetup(benchmark::State& state) {
  Eigen::setNbThreads(1);
  const SessionConfig& c = prostateConfig();
  int nodes = 0, points = 0;
  for (auto _ : state) {
    const Session s(c);
    nodes = s.mesh().nodes();
    points = static_cast<int>(s.tissue().path().size());
    benchmark::DoNotOptimize(nodes);
  }
  state.counters["nodes"] = nodes;
  state.counters["path_points"] = points;
}

void prostateStep(benchmark::State& state) {
  Eigen::setNbThreads(1);
  const SessionConfig& c = prostateConfig();
  Session s(c);
  const double dt = 1e-3;
  double depth = -0.5e-3;
  while (depth < 0.02) s.step(s.poseAtDepth(depth += 10e-3 * dt), dt);
  double dir = 1.0;
  for (auto _ : state) {
    depth += dir * 3e-3 * dt;
    if (depth > 0.022 || depth < 0.02) dir = -dir;
    benchmark::DoNotOptimize(s.step(s.poseAtDepth(depth), dt).axial_force);
  }
  state.counters["steps_per_s"] = benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
  state.counters["nodes"] = s.mesh().nodes();
  state.counters["coupled"] = s.last().coupled;
  state.counters["path_dofs"] = s.tissue().dynamics().pathDofs();
}
}  // namespace

static void BM_Prostate_Setup(benchmark::State& st) { prostateSetup(st); }
BENCHMARK(BM_Prostate_Setup)->Unit(benchmark::kMillisecond)->Iterations(1);
static void BM_Prostate_Step(benchmark::State& st) { prostateStep(st); }
BENCHMARK(BM_Prostate_Step)->Unit(benchmark::kMicrosecond)->MinTime(2.0);
static void BM_Block10496_Reduced(benchmark::State& st) { run(st, 41, 16, Backend::Reduced); }
BENCHMARK(BM_Block10496_Reduced)->Unit(benchmark::kMicrosecond)->MinTime(2.0);
static void BM_Block10496_Reduced_Spacing2mm(benchmark::State& st) { run(st, 41, 16, Backend::Reduced, 2e-3); }
BENCHMARK(BM_Block10496_Reduced_Spacing2mm)->Unit(benchmark::kMicrosecond)->MinTime(2.0);
static void BM_Setup_Block10496(benchmark::State& st) { setup(st, 41, 16); }
BENCHMARK(BM_Setup_Block10496)->Unit(benchmark::kMillisecond)->Iterations(1);
static void BM_Setup_Block50225(benchmark::State& st) { setup(st, 41, 35); }
BENCHMARK(BM_Setup_Block50225)->Unit(benchmark::kMillisecond)->Iterations(1);
static void BM_Block50225_Reduced(benchmark::State& st) { run(st, 41, 35, Backend::Reduced); }
BENCHMARK(BM_Block50225_Reduced)->Unit(benchmark::kMicrosecond)->MinTime(2.0);
static void BM_Block10496_FieldSnapshot(benchmark::State& st) { fieldSnapshot(st); }
BENCHMARK(BM_Block10496_FieldSnapshot)->Unit(benchmark::kMicrosecond)->MinTime(1.0);
static void BM_Block10496_FieldFromSnapshot(benchmark::State& st) { fieldFromSnapshot(st); }
BENCHMARK(BM_Block10496_FieldFromSnapshot)->Unit(benchmark::kMillisecond)->MinTime(1.0);

BENCHMARK_MAIN();
