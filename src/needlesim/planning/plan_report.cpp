// What `needlesim plan` reports (plan_run.hpp reportPlan): tables, results, projections,
// the error histogram, notes, and the path as a ParaView polyline.
#include <fmt/format.h>

#include <algorithm>
#include <cstdio>
#include <cmath>
#include <numbers>

#include "needlesim/io/field_series.hpp"
#include "needlesim/planning/plan_run.hpp"
#include "needlesim/scenario/scenario.hpp"

namespace needlesim::planning {
namespace {

constexpr double pi = std::numbers::pi;
constexpr double kDeg = 180.0 / pi;

// plan.csv: one row per arc, with the retraction and the rotation before it and the depths it
// spans (a retraction pulls the tip back from the previous row's insert_to to insert_from).
io::Table planTable(const PlanProblem& pb, const Plan& plan) {
  io::Table t({{"arc", "1"}, {"retract_before", "m"}, {"rotate_before", "rad"}, {"insert_from", "m"},
               {"insert_to", "m"}, {"curvature", "1/m"}, {"duty_cycle", "1"}});
  double s = 0.0;
  for (std::size_t i = 0; i < plan.arcs.size(); ++i) {
    const Arc& a = plan.arcs[i];
    const double duty = pb.kappa > 0 ? std::max(0.0, 1.0 - a.curvature / pb.kappa) : 0.0;
    s -= a.retract;
    t.addRow({static_cast<double>(i + 1), a.retract, i == 0 ? plan.roll : a.rotate, s, s + a.length, a.curvature, duty});
    s += a.length;
  }
  return t;
}

// Smallest distance of a point to the surfaces of the obstacles.
double clearanceAt(const PlanProblem& pb, const Vec3& p) {
  double d = std::numeric_limits<double>::infinity();
  for (const Obstacle& o : pb.obstacles) d = std::min(d, o.distance(p));
  return std::isfinite(d) ? d : 0.0;
}

io::Table pathTable(const PlanProblem& pb, const std::vector<Vec3>& points) {
  io::Table t({{"insertion", "m"}, {"x", "m"}, {"y", "m"}, {"z", "m"}, {"clearance", "m"}});
  double s = 0.0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (i > 0) s += (points[i] - points[i - 1]).norm();
    t.addRow({s, points[i].x(), points[i].y(), points[i].z(), clearanceAt(pb, points[i])});
  }
  return t;
}

io::Table errorTable(const PlanOutcome& o) {
  const bool closed = o.closed_loop.has_value(), retracts = closed && o.problem.max_retractions > 0;
  std::vector<io::Column> cols{{"sample", "1"}, {"error_open_loop", "m"}, {"touch_open_loop", "1"}};
  if (closed) cols.insert(cols.end(), {{"error_closed_loop", "m"}, {"touch_closed_loop", "1"}});
  if (retracts) cols.insert(cols.end(), {{"retractions_closed_loop", "1"}, {"retracted_to_closed_loop", "m"}});
  io::Table t(cols);
  for (std::size_t i = 0; i < o.open_loop->errors.size(); ++i) {
    std::vector<double> row{static_cast<double>(i + 1), o.open_loop->errors[i], double(o.open_loop->touched[i])};
    if (closed) row.insert(row.end(), {o.closed_loop->errors[i], double(o.closed_loop->touched[i])});
    if (retracts) row.insert(row.end(), {double(o.closed_loop->retractions[i]), o.closed_loop->retracted_to[i]});
    t.addRow(row);
  }
  return t;
}

// A circle of radius r about (cx, cy), in mm.
io::PlotSeries circle(const std::string& label, double cx, double cy, double r, bool dashed) {
  io::PlotSeries s{label, {}, {}, false, dashed};
  for (int i = 0; i <= 72; ++i) {
    s.x.push_back(1e3 * (cx + r * std::cos(2 * pi * i / 72)));
    s.y.push_back(1e3 * (cy + r * std::sin(2 * pi * i / 72)));
  }
  return s;
}

// An obstacle's outline (and its clearance, dashed) in the projection onto axes (a, b).
void obstacleOutline(const Obstacle& o, int a, int b, const PlanProblem& pb, io::Plot& plot) {
  for (const bool withClearance : {false, true}) {
    const double r = o.radius + (withClearance ? o.clearance : 0.0);
    const std::string label = o.name + (withClearance ? " + clearance" : "");
    if (!o.cylinder || (a != 2 && b != 2)) {
      plot.series.push_back(circle(label, o.centre[a], o.centre[b], r, withClearance));
      continue;
    }
    const int across = a == 2 ? b : a;  // the cylinder's axis is z: a rectangle across the other axis
    io::PlotSeries s{label, {}, {}, false, withClearance};
    const double u0 = o.centre[across] - r, u1 = o.centre[across] + r, z0 = pb.lo.z(), z1 = pb.hi.z();
    for (const auto& [u, z] : {std::pair{u0, z0}, {u0, z1}, {u1, z1}, {u1, z0}, {u0, z0}}) {
      s.x.push_back(1e3 * (a == 2 ? z : u));
      s.y.push_back(1e3 * (a == 2 ? u : z));
    }
    plot.series.push_back(s);
  }
}

io::Plot projection(const PlanOutcome& o, const std::vector<Vec3>& pts, int a, int b) {
  static const char* names[3] = {"depth x", "lateral y", "elevation z"};
  io::Plot p{fmt::format("planned path: {} - {}", names[a], names[b]), fmt::format("{} [mm]", names[a]),
             fmt::format("{} [mm]", names[b]), {}};
  io::PlotSeries path{"tip path", {}, {}, false, false};
  for (const Vec3& q : pts) path.x.push_back(1e3 * q[a]), path.y.push_back(1e3 * q[b]);
  p.series.push_back(path);
  const PlanProblem& pb = o.problem;
  p.series.push_back(io::PlotSeries{"target", {1e3 * pb.target[a]}, {1e3 * pb.target[b]}, true, false});
  p.series.push_back(circle("tolerance", pb.target[a], pb.target[b], pb.tolerance, true));
  for (const Obstacle& ob : pb.obstacles) obstacleOutline(ob, a, b, pb, p);
  return p;
}

io::Plot histogram(const PlanOutcome& o) {
  io::Plot p{"targeting error (Monte Carlo)", "error [mm]", "fraction of samples", {}};
  double top = 0.0;
  for (const auto* e : {&o.open_loop, &o.closed_loop})
    if (e->has_value()) top = std::max(top, *std::max_element((*e)->errors.begin(), (*e)->errors.end()));
  const int bins = 30;
  const double w = top > 0 ? top / bins : 1e-3;
  for (const auto* e : {&o.open_loop, &o.closed_loop}) {
    if (!e->has_value()) continue;
    std::vector<double> count(bins, 0.0);
    for (double v : (*e)->errors)
      if (v >= 0) count[std::min(bins - 1, static_cast<int>(v / w))] += 1.0 / (*e)->errors.size();
    io::PlotSeries s{e == &o.open_loop ? "open loop" : "closed loop", {}, {}, false, e != &o.open_loop};
    for (int i = 0; i < bins; ++i)
      for (const double edge : {i * w, (i + 1) * w}) s.x.push_back(1e3 * edge), s.y.push_back(count[i]);
    p.series.push_back(s);
  }
  return p;
}

// The path as a polyline (Line cells) for ParaView, with its insertion depth and clearance.
void pathPolyline(const PlanProblem& pb, const std::vector<Vec3>& pts, ResultSink& sink) {
  io::FieldSeries* f = sink.fields("planned_path", 3);
  if (!f || pts.size() < 2) return;
  std::vector<double> xyz, depth, clear;
  std::vector<int> lines;
  double s = 0.0;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    if (i > 0) s += (pts[i] - pts[i - 1]).norm(), lines.insert(lines.end(), {int(i - 1), int(i)});
    xyz.insert(xyz.end(), {pts[i].x(), pts[i].y(), pts[i].z()});
    depth.push_back(s);
    clear.push_back(clearanceAt(pb, pts[i]));
  }
  f->setMesh(xyz, io::CellType::Line, lines);
  f->beginStep(0.0);
  f->pointData("insertion", depth, 1, "m");
  f->pointData("clearance", clear, 1, "m");
  f->endStep();
}

void planResults(const PlanOutcome& o, ResultSink& sink) {
  const SearchResult& s = o.search;
  const Plan& plan = s.best.plan;
  sink.result("feasible", s.feasible ? 1.0 : 0.0, "1", "1: a plan reaches the target and keeps every clearance");
  sink.result("planned_miss", s.best.miss, "m", s.feasible ? "planned distance of the tip from the target"
                                                            : "closest approach of the best path found");
  sink.result("entry_offset", plan.entry_offset, "m", "entry point on the entry face (insertion.entry_offset)");
  sink.result("entry_angle", plan.entry_angle, "rad", "entry angle to the face (insertion.entry_angle)");
  sink.result("bevel_roll", plan.roll, "rad", "bevel orientation at entry (insertion.bevel_orientation)");
  sink.result("rotations", plan.rotations(), "1", "axial rotations of the bevel during the insertion");
  sink.result("path_length", plan.length(), "m", "inserted length of the tip path");
  sink.result("curvature", o.problem.kappa, "1/m", "curvature of the needle with the bevel fixed (kinematic model)");
  for (std::size_t k = 0; k < s.best.distances.size(); ++k)
    sink.result("clearance_" + o.problem.obstacles[k].name, s.best.distances[k], "m",
                fmt::format("smallest distance of the needle axis to the surface (required {:.3g} mm)",
                            o.problem.obstacles[k].clearance * 1e3));
  sink.result("planning_time", s.seconds, "s", "wall time of the search (one core)");
  sink.result("paths_evaluated", static_cast<double>(s.paths), "1", "candidate paths traced and checked");
  sink.result("paths_per_second", s.seconds > 0 ? s.paths / s.seconds : 0.0, "1/s", "paths_evaluated / planning_time");
  sink.result("last_arcs_solved", static_cast<double>(s.partial), "1", "entry and arc prefixes solved for the last arc");
}

void errorResults(const PlanOutcome& o, ResultSink& sink) {
  if (o.open_loop) {
    sink.result("error_p50", o.open_loop->p50, "m", "open loop: median targeting error");
    sink.result("error_p95", o.open_loop->p95, "m", "open loop: 95th percentile of the targeting error");
    sink.result("touch_probability", o.open_loop->touch_probability, "1", "open loop: probability of touching an obstacle");
  }
  if (o.closed_loop) {
    sink.result("closed_loop_error_p50", o.closed_loop->p50, "m", "closed loop: median targeting error");
    sink.result("closed_loop_error_p95", o.closed_loop->p95, "m", "closed loop: 95th percentile of the targeting error");
    sink.result("closed_loop_touch_probability", o.closed_loop->touch_probability, "1",
                "closed loop: probability of touching an obstacle");
    sink.result("closed_loop_rotations", o.closed_loop->mean_rotations, "1", "closed loop: mean axial rotations");
  }
  if (o.closed_loop && o.problem.max_retractions > 0) {
    sink.result("closed_loop_retractions", o.closed_loop->mean_retractions, "1", "closed loop: mean retractions per insertion");
    sink.result("closed_loop_retracting_share", o.closed_loop->retracting_share, "1",
                "closed loop: share of the insertions that retract");
    sink.result("closed_loop_retracted_to", o.closed_loop->mean_retracted_to, "m",
                "closed loop: mean depth a retraction pulls the tip back to");
  }
}

std::string actionsText(const Plan& plan) {
  std::string text = fmt::format("enter at offset {:.4g} mm, angle {:.4g} deg, bevel roll {:.4g} deg", plan.entry_offset * 1e3,
                                 plan.entry_angle * kDeg, plan.roll * kDeg);
  double s = 0.0;
  for (std::size_t i = 0; i < plan.arcs.size(); ++i) {
    const Arc& a = plan.arcs[i];
    if (a.retract > 0) text += fmt::format("; retract to {:.4g} mm", (s - a.retract) * 1e3);
    s -= a.retract;
    if (i > 0) text += fmt::format("; at {:.4g} mm rotate {:.4g} deg", s * 1e3, a.rotate * kDeg);
    s += a.length;
    text += fmt::format("; insert to {:.4g} mm (curvature {:.4g} 1/m)", s * 1e3, a.curvature);
  }
  return text;
}

void planNotes(const Scenario& sc, const PlanOutcome& o, ResultSink& sink) {
  const SearchResult& s = o.search;
  if (s.feasible)
    sink.note(fmt::format("Plan ({} rotation(s), chosen by {} among {} found): {}.", s.best.plan.rotations(), o.chosen_by,
                          s.found.size(), actionsText(s.best.plan)));
  else
    sink.warning(fmt::format("No plan: {}. path.csv holds the closest approach: {}.", s.reason, actionsText(s.best.plan)));
  sink.note(fmt::format("Search: sampling-based with an analytic last arc over the kinematic bevel-tip model "
                        "(Webster et al. 2006), rotation counts searched in turn from 0 up to {} (of at most {}); {} "
                        "paths checked in {:.3g} s (docs/planning.md).", s.rotations_searched, o.problem.max_rotations,
                        s.paths, s.seconds));
  if (o.open_loop)
    sink.note(fmt::format("Targeting error over {} Monte Carlo samples of the kinematic model (curvature sd {:g}, modulus sd "
                          "{:g}, target sd {:g} mm, entry sd {:g} mm, angle sd {:g} deg){}.", sc.plan.uncertainty.samples,
                          sc.plan.uncertainty.curvature_sd, sc.plan.uncertainty.modulus_sd,
                          sc.plan.uncertainty.target_sd * 1e3, sc.plan.uncertainty.entry_sd * 1e3,
                          sc.plan.uncertainty.angle_sd * kDeg,
                          o.closed_loop ? fmt::format("; closed loop: tip and target measured every {:g} mm with {:g} mm "
                                                      "noise, the last arc replanned", sc.plan.uncertainty.measure_every * 1e3,
                                                      sc.plan.uncertainty.measurement_noise * 1e3)
                                        : ""));
  if (o.closed_loop && o.problem.max_retractions > 0)
    sink.note(fmt::format("Closed loop with up to {} retraction(s): {:.3g} % of the insertions retract ({:.3g} per insertion, "
                          "to {:.4g} mm on average){}.", o.problem.max_retractions, 100 * o.closed_loop->retracting_share,
                          o.closed_loop->mean_retractions, o.closed_loop->mean_retracted_to * 1e3,
                          o.closed_loop->retracting_example.arcs.empty()
                              ? std::string()
                              : "; closed_loop_retracting.csv holds the actions of the first that does"));
}

}  // namespace

void reportPlan(const Scenario& sc, const PlanOutcome& o, ResultSink& sink) {
  const PlanProblem& pb = o.problem;
  sink.table("plan", planTable(pb, o.search.best.plan));
  sink.table("path", pathTable(pb, o.search.best.points));
  if (o.open_loop) sink.table("error_distribution", errorTable(o));
  if (o.closed_loop && !o.closed_loop->retracting_example.arcs.empty())
    sink.table("closed_loop_retracting", planTable(pb, o.closed_loop->retracting_example));
  planResults(o, sink);
  errorResults(o, sink);
  planNotes(sc, o, sink);
  sink.plot(projection(o, o.search.best.points, 0, 1));
  sink.plot(projection(o, o.search.best.points, 0, 2));
  sink.plot(projection(o, o.search.best.points, 1, 2));
  if (o.open_loop) sink.plot(histogram(o));
  pathPolyline(pb, o.search.best.points, sink);
}

}  // namespace needlesim::planning
