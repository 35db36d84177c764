// The plan executed by a physics engine (verify.hpp).
#include "needlesim/planning/verify.hpp"

#include <fmt/format.h>

#include <chrono>

#include "needlesim/core/error.hpp"
#include "needlesim/engines/memory_sink.hpp"
#include "needlesim/results/results_folder.hpp"
#include "needlesim/scenario/scenario.hpp"

namespace needlesim::planning {
namespace {

Vec3 lastRow(const io::Table& t, const std::string& x, const std::string& y, const std::string& z) {
  const std::size_t r = t.rows() - 1;
  return {t.at(r, t.columnIndex(x)), t.at(r, t.columnIndex(y)), t.at(r, t.columnIndex(z))};
}

// The target's displacement at the end of the run (an inclusion target; a point does not move).
Vec3 targetMotion(const Scenario& sc, const MemorySink& m) {
  const auto it = m.tables.find("inclusions");
  if (sc.plan.target.empty() || it == m.tables.end() || it->second.rows() == 0) return Vec3::Zero();
  const std::string& n = sc.plan.target;
  return lastRow(it->second, n + "_ux", n + "_uy", n + "_uz");
}

}  // namespace

void checkVerifyEngine(const std::string& engine) {
  if (engine != "realtime3d")
    throw InputError(commandLine(), "--verify", engine, "is not an engine the plan can be verified in",
                     "realtime3d (it moves the bevel with its roll in a deforming 3D tissue)");
}

Verification verifyPlan(const Scenario& sc, const PlanOutcome& o, const std::string& engine) {
  Scenario run = planAsScenario(sc, o.search.best.plan, o.problem.kappa);
  run.model.engine = engine;
  // the needle follows the channel its tip cuts, turning at the plan's curvature
  run.model.realtime3d.follow_tip = true;
  run.model.realtime3d.curvature = o.problem.kappa;
  // realtime3d models spherical inclusions only: a cylinder (a vessel) is left out of the run
  std::erase_if(run.tissue.inclusions, [](const InclusionSpec& I) { return I.shape != InclusionSpec::Shape::Sphere; });
  const auto t0 = std::chrono::steady_clock::now();
  const MemorySink m = runInMemory(run);
  Verification v;
  v.engine = engine;
  v.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const Vec3 tip = lastRow(m.tables.at("forces"), "tip_x", "tip_y", "tip_z");
  const Vec3 moved = targetMotion(sc, m);
  v.planned_miss = o.search.best.miss;
  v.executed_miss = (tip - o.problem.target - moved).norm();
  v.tip_gap = (tip - o.search.best.points.back()).norm();
  if (m.results.count("tip_tissue_displacement_x")) {
    const Vec3 u(m.results.at("tip_tissue_displacement_x").value, m.results.at("tip_tissue_displacement_y").value,
                 m.results.at("tip_tissue_displacement_z").value);
    v.tip_motion = u.norm();
    v.channel_gap = (tip - u - o.search.best.points.back()).norm();
  }
  v.target_motion = moved.norm();
  return v;
}

std::string reportVerification(const Verification& v, ResultSink& sink) {
  sink.result("executed_miss", v.executed_miss, "m", "engine " + v.engine + ": tip to the (displaced) target at the end");
  sink.result("executed_tip_gap", v.tip_gap, "m", "engine " + v.engine + ": tip to the planned tip");
  sink.result("executed_tip_motion", v.tip_motion, "m",
              "engine " + v.engine + ": the tissue's displacement at the tip (deformation), part of the tip gap");
  sink.result("executed_channel_gap", v.channel_gap, "m",
              "engine " + v.engine + ": the channel's end (the tip less the tissue's displacement there) to the planned tip "
              "(steering model)");
  sink.result("target_motion", v.target_motion, "m", "engine " + v.engine + ": displacement of the target (tissue deformation)");
  sink.result("verify_time", v.seconds, "s", "wall time of the engine's run");
  const std::string text = fmt::format(
      "Checked in engine {}: executed miss {:.3g} mm beside the planned {:.3g} mm. The engine's tip is {:.3g} mm from the "
      "planned tip: the tissue's deformation moved it {:.3g} mm, and the channel it cut ends {:.3g} mm from the plan's "
      "(the steering model); the tissue's deformation moved the target by {:.3g} mm. The executed miss is at most the "
      "planned miss plus the tip gap and the target's motion.",
      v.engine, v.executed_miss * 1e3, v.planned_miss * 1e3, v.tip_gap * 1e3, v.tip_motion * 1e3, v.channel_gap * 1e3,
      v.target_motion * 1e3);
  sink.note(text);
  return text;
}

PlanFolder planAndVerifyToFolder(const Scenario& sc, const std::string& engine, const std::filesystem::path& target,
                                 bool overwrite) {
  const auto t0 = std::chrono::steady_clock::now();
  io::ResultsFolder folder(sc, target);
  PlanFolder out;
  out.outcome = planScenario(sc);
  reportPlan(sc, out.outcome, folder);
  if (out.outcome.search.feasible)
    out.verified = reportVerification(verifyPlan(sc, out.outcome, engine), folder);
  else
    folder.note("No plan to verify in engine " + engine + ".");
  folder.commit(overwrite, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  out.folder = folder.target();
  out.files = folder.files();
  return out;
}

}  // namespace needlesim::planning
