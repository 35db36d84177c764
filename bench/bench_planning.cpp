// The path planner (docs/planning.md): a whole search on the planning examples, and one
// candidate path traced and checked (paths evaluated per second per core; goal >= 10k/s).
#include <benchmark/benchmark.h>

#include "needlesim/planning/plan_run.hpp"
#include "needlesim/scenario/reader.hpp"
#include "needlesim/scenario/scenario.hpp"

using namespace needlesim;
using namespace needlesim::planning;

static void searchExample(benchmark::State& st, const char* file) {
  const Scenario sc = scenario::readFile(std::string(NEEDLESIM_EXAMPLES_DIR) + file);
  const PlanProblem pb = planProblem(sc);
  long paths = 0;
  for (auto _ : st) {
    const SearchResult r = searchPlan(pb);
    paths += r.paths;
    benchmark::DoNotOptimize(r.best.miss);
  }
  st.counters["paths_per_search"] = static_cast<double>(paths) / static_cast<double>(st.iterations());
  st.counters["paths_per_s"] = benchmark::Counter(static_cast<double>(paths), benchmark::Counter::kIsRate);
}

static void BM_PlanGelBlock(benchmark::State& st) { searchExample(st, "planning/gel_block.yaml"); }
BENCHMARK(BM_PlanGelBlock)->Unit(benchmark::kMillisecond);

static void BM_PlanProstateVessel(benchmark::State& st) { searchExample(st, "planning/prostate_vessel.yaml"); }
BENCHMARK(BM_PlanProstateVessel)->Unit(benchmark::kMillisecond);

// One candidate: a 93 mm arc traced every 0.5 mm and checked against the vessel and the tissue.
static void BM_CheckOnePath(benchmark::State& st) {
  const Scenario sc = scenario::readFile(std::string(NEEDLESIM_EXAMPLES_DIR) + "planning/gel_block.yaml");
  const PlanProblem pb = planProblem(sc);
  const Plan plan = searchPlan(pb).best.plan;
  for (auto _ : st) benchmark::DoNotOptimize(checkPlan(pb, plan).miss);
  st.SetItemsProcessed(st.iterations());
}
BENCHMARK(BM_CheckOnePath);

// The open-loop Monte Carlo of the gel example (1000 samples).
static void BM_OpenLoopErrors1000(benchmark::State& st) {
  const Scenario sc = scenario::readFile(std::string(NEEDLESIM_EXAMPLES_DIR) + "planning/gel_block.yaml");
  const PlanProblem pb = planProblem(sc);
  const Plan plan = searchPlan(pb).best.plan;
  for (auto _ : st) benchmark::DoNotOptimize(openLoopErrors(pb, plan, sc.plan.uncertainty).p95);
}
BENCHMARK(BM_OpenLoopErrors1000)->Unit(benchmark::kMillisecond);

BENCHMARK_MAIN();
