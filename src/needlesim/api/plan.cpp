// api::plan: the path planner (planning/plan_run.hpp) in memory or into a results folder.
#include "needlesim/api/scenario_impl.hpp"
#include "needlesim/api/translate.hpp"
#include "needlesim/engines/memory_sink.hpp"
#include "needlesim/planning/plan_run.hpp"
#include "needlesim/results/results_folder.hpp"

namespace needlesim::api {

Results plan(const Scenario& scenario) {
  return detail::translated([&] {
    const needlesim::Scenario& sc = detail::ScenarioAccess::typed(scenario);
    MemorySink sink;
    planning::reportPlan(sc, planning::planScenario(sc), sink);
    return detail::memoryResults(sink);
  });
}

Results plan(const Scenario& scenario, const std::filesystem::path& folder, const RunSettings& settings) {
  return detail::translated([&] {
    const needlesim::Scenario& sc = detail::ScenarioAccess::typed(scenario);
    const planning::PlanFolder f = planning::planToFolder(sc, folder, settings.overwrite);
    MemorySink sink;
    planning::reportPlan(sc, f.outcome, sink);  // the tables and results as written
    Results r = detail::memoryResults(sink);
    r.folder = f.folder;
    detail::readFolder(r);
    return r;
  });
}

}  // namespace needlesim::api
