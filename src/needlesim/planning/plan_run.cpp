// Plan a scenario, predict its error, write its results folder (plan_run.hpp).
#include "needlesim/planning/plan_run.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>

#include "needlesim/engines/steering/kinematic.hpp"
#include "needlesim/results/results_folder.hpp"
#include "needlesim/scenario/scenario.hpp"

namespace needlesim::planning {
namespace {

// choose: risk: the feasible plan (of the fewest rotations) with the lowest obstacle-touch
// probability, then the lowest p95 error, under the open-loop spreads.
void chooseByRisk(const Scenario& sc, PlanOutcome& o) {
  double best_touch = 2.0, best_p95 = 0.0;
  std::size_t best = 0;
  for (std::size_t i = 0; i < o.search.found.size(); ++i) {
    const ErrorDistribution e = openLoopErrors(o.problem, o.search.found[i].plan, sc.plan.uncertainty);
    if (e.touch_probability < best_touch || (e.touch_probability == best_touch && e.p95 < best_p95)) {
      best_touch = e.touch_probability;
      best_p95 = e.p95;
      best = i;
    }
  }
  o.search.best = o.search.found[best];
  o.chosen_by = "risk";
}

// An infeasible target off the insertion plane that an entry at its elevation would reach: the
// reason says so, and that a scenario's insertion cannot state that entry (docs/planning.md,
// Assumptions).
void explainOutOfPlane(PlanOutcome& o) {
  const PlanProblem& pb = o.problem;
  if (o.search.feasible || std::abs(pb.target.z()) <= pb.tolerance) return;
  PlanProblem raised = pb;
  raised.entry_elevation = std::clamp(pb.target.z(), pb.lo.z(), pb.hi.z());
  raised.max_paths = std::min(pb.max_paths, 20000L);
  const SearchResult r = searchPlan(raised);
  if (!r.feasible) return;
  o.search.reason += fmt::format(
      "; an entry {:.3g} mm out of the insertion plane (at the target's elevation) would reach it (planned miss {:.3g} mm), "
      "but the scenario's insertion places the entry point and direction in the insertion plane (insertion.entry_offset "
      "across the width, insertion.entry_angle in the plane; docs/planning.md, Assumptions)",
      raised.entry_elevation * 1e3, r.best.miss * 1e3);
}

}  // namespace

PlanOutcome planScenario(const Scenario& sc) {
  PlanOutcome o;
  o.problem = planProblem(sc);
  o.search = searchPlan(o.problem);
  explainOutOfPlane(o);
  o.chosen_by = "clearance";
  const PlanUncertaintySpec& u = sc.plan.uncertainty;
  if (o.search.feasible && sc.plan.choose == "risk") chooseByRisk(sc, o);
  if (u.samples > 0 && !o.search.best.plan.arcs.empty()) {
    o.open_loop = openLoopErrors(o.problem, o.search.best.plan, u);
    if (u.measure_every > 0) o.closed_loop = closedLoopErrors(o.problem, o.search.best.plan, u);
  }
  return o;
}

Scenario planAsScenario(const Scenario& sc, const Plan& plan, double kappa) {
  Scenario out = sc;
  InsertionSpec& in = out.insertion;
  double speed = 1e-3;  // m/s, the scenario's first insertion speed
  for (const MotionSegment& m : sc.insertion.segments)
    if (m.kind == MotionSegment::Kind::Insert) {
      speed = m.speed;
      break;
    }
  in.entry_offset = plan.entry_offset;
  in.entry_angle = plan.entry_angle;
  in.bevel_orientation = plan.roll;
  in.start_depth = 0.0;
  in.segments.clear();
  double depth = 0.0;
  constexpr double kRate = std::numbers::pi;  // rad/s of the axial rotations
  for (std::size_t i = 0; i < plan.arcs.size(); ++i) {
    const Arc& a = plan.arcs[i];
    if (a.retract > 0.0) {  // back along the channel, at the insertion speed
      MotionSegment r;
      r.kind = MotionSegment::Kind::Retract;
      r.speed = speed;
      depth -= a.retract;
      r.to_depth = depth;
      in.segments.push_back(r);
    }
    if (i > 0 && a.rotate != 0.0) {
      MotionSegment r;
      r.kind = MotionSegment::Kind::Rotate;
      r.angle = a.rotate;
      r.rate = kRate;
      r.duration = std::abs(a.rotate) / kRate;
      in.segments.push_back(r);
    }
    MotionSegment m;
    m.speed = speed;
    depth += a.length;
    m.to_depth = depth;
    if (kappa > 0 && a.curvature < kappa * (1 - 1e-9)) {  // duty-cycled: one spin per 1 mm of insertion
      m.duty_cycle = steering::dutyCycleFor(kappa, a.curvature);
      m.rate = m.duty_cycle > 0 ? speed * 2 * std::numbers::pi / (1e-3 * m.duty_cycle) : 0.0;
    }
    in.segments.push_back(m);
  }
  out.plan.given = false;
  return out;
}

PlanFolder planToFolder(const Scenario& sc, const std::filesystem::path& target, bool overwrite) {
  const auto t0 = std::chrono::steady_clock::now();
  io::ResultsFolder folder(sc, target);
  PlanFolder out;
  out.outcome = planScenario(sc);
  reportPlan(sc, out.outcome, folder);
  folder.commit(overwrite, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  out.folder = folder.target();
  out.files = folder.files();
  return out;
}

}  // namespace needlesim::planning
