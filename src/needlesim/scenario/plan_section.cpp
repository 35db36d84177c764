// The plan section (scenario/plan_section.hpp), each field declared once
// (scenario/parameter_table.hpp), and the checks across it and the tissue it names.
#include "needlesim/scenario/plan_section.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "needlesim/core/nearest_name.hpp"
#include "needlesim/scenario/parameter_table.hpp"
#include "needlesim/scenario/scenario.hpp"

namespace needlesim::scenario {
namespace {

namespace D = units::dim;
constexpr double kDeg = std::numbers::pi / 180.0;

ParamTable<PlanAvoidSpec> makeAvoid() {
  using A = PlanAvoidSpec;
  ParamTable<A> t("plan_avoid");
  FieldDoc name = t.otherDoc("inclusion", Kind::String, "", "the name of an inclusion of tissue.inclusions");
  name.required = true;
  t.row(std::move(name), [](Section& s, A& a, const Scenario&) { a.inclusion = s.text("inclusion"); })
      .quantity(&A::clearance, "clearance", D::Length, "mm", nonNegative(),
                "smallest distance kept between the needle axis and the inclusion's surface");
  return t;
}

ParamTable<PlanUncertaintySpec> makeUncertainty() {
  using U = PlanUncertaintySpec;
  ParamTable<U> t("plan_uncertainty");
  t.count(&U::samples, "samples", 0.0, 1e6, "Monte Carlo samples of the targeting error (0 = no prediction)")
      .count(&U::seed, "seed", 0.0, 2e9, "random seed of the samples")
      .number(&U::curvature_sd, "curvature_sd", closedOpen(0.0, 1.0), "relative standard deviation of the curvature")
      .number(&U::modulus_sd, "modulus_sd", closedOpen(0.0, 1.0),
              "relative standard deviation of the tissue's modulus (the curvature scales as modulus^-1/4)")
      .quantity(&U::target_sd, "target_sd", D::Length, "mm", nonNegative(),
                "standard deviation of the target position, per axis")
      .quantity(&U::entry_sd, "entry_sd", D::Length, "mm", nonNegative(),
                "standard deviation of the entry point on the entry face, per axis")
      .quantity(&U::angle_sd, "angle_sd", D::Angle, "deg", closedOpen(0.0, 30 * kDeg),
                "standard deviation of the entry direction, per axis")
      .quantity(&U::measurement_noise, "measurement_noise", D::Length, "mm", nonNegative(),
                "closed loop: standard deviation of a tip position measurement, per axis")
      .quantity(&U::measure_every, "measure_every", D::Length, "mm", nonNegative(),
                "closed loop: insertion between tip measurements, each followed by replanning (0 = open loop)");
  return t;
}

const ParamTable<PlanAvoidSpec>& avoidTable() {
  static const auto t = makeAvoid();
  return t;
}
const ParamTable<PlanUncertaintySpec>& uncertaintyTable() {
  static const auto t = makeUncertainty();
  return t;
}

void readAvoid(Section& s, PlanSpec& p, const Scenario& sc) {
  const auto items = s.list("avoid");
  for (std::size_t i = 0; i < items.size(); ++i) {
    Section e = s.element(items[i], "avoid", i);
    PlanAvoidSpec a;
    avoidTable().read(e, a, sc);
    p.avoid.push_back(a);
  }
}

ParamTable<PlanSpec> makePlan() {
  using P = PlanSpec;
  ParamTable<P> t("plan");
  t.text(&P::target, "target", "target_depth, _lateral, _elevation",
         "the inclusion aimed at (one marked target: true); or give the point as target_depth, target_lateral, "
         "target_elevation")
      .optional(&P::target_depth, "target_depth", D::Length, nonNegative(), "target point: depth from the entry face")
      .quantity(&P::target_lateral, "target_lateral", D::Length, "mm", anyValue(), "target point: across the width")
      .quantity(&P::target_elevation, "target_elevation", D::Length, "mm", anyValue(), "target point: across the height")
      .quantity(&P::tolerance, "tolerance", D::Length, "mm", positive(), "largest planned distance from the target")
      .row(t.otherDoc("avoid", Kind::List, "", "the inclusions to keep away from, each with its clearance", "plan_avoid"),
           readAvoid)
      .quantity(&P::entry_window, "entry_window", D::Length, "mm", nonNegative(),
                "entry points searched: insertion.entry_offset +- this, along the entry face in the insertion plane")
      .quantity(&P::max_entry_angle, "max_entry_angle", D::Angle, "deg", closedOpen(0.0, 90 * kDeg),
                "entry directions searched: insertion.entry_angle +- this, in the insertion plane")
      .flag(&P::duty_cycling, "duty_cycling", "the last arc may be duty-cycled (spun) to a lower curvature")
      .number(&P::curvature_reserve, "curvature_reserve", closedOpen(0.0, 1.0),
              "share of the needle's curvature the plan keeps in hand for corrections: its arcs curve at (1 - this) "
              "times the curvature (duty-cycled)")
      .count(&P::max_rotations, "max_rotations", 0.0, 8.0, "most axial rotations of the bevel during the insertion")
      .count(&P::max_retractions, "max_retractions", 0.0, 8.0,
             "closed loop: most retractions per insertion; where the estimated tip can no longer reach the target "
             "within the tolerance, it is pulled back along its channel to where it can, turned and re-inserted")
      .derived(&P::max_depth, "max_depth", D::Length, positive(), "the needle's length",
               [](const P&, const Scenario& sc) { return sc.needle.length; }, "longest insertion (tip path length)")
      .quantity(&P::sample_spacing, "sample_spacing", D::Length, "mm", openClosed(0.0, 0.01),
                "spacing of the path points checked against the obstacles (the check keeps half of it in hand)")
      .count(&P::max_paths, "max_paths", 1.0, 1e8, "search budget: candidate paths evaluated")
      .count(&P::seed, "seed", 0.0, 2e9, "random seed of the search")
      .word(&P::choose, "choose", {"clearance", "risk"},
            "among the plans found with the fewest rotations: the largest clearance, or the lowest predicted "
            "risk (obstacle-touch probability, then p95 targeting error; needs uncertainty.samples)")
      .row(t.otherDoc("uncertainty", Kind::Section, "", "distributions of the predicted targeting error",
                      "plan_uncertainty"),
           [](Section& s, P& p, const Scenario& sc) {
             Section u = s.sub("uncertainty");
             uncertaintyTable().read(u, p.uncertainty, sc);
           });
  return t;
}

const ParamTable<PlanSpec>& planTable() {
  static const auto t = makePlan();
  return t;
}

const InclusionSpec* inclusionNamed(Section& s, const std::string& key, const std::string& name, const Scenario& sc) {
  std::vector<std::string> names;
  for (const InclusionSpec& I : sc.tissue.inclusions) {
    if (I.name == name) return &I;
    names.push_back(I.name);
  }
  const std::string near = nearestName(name, names);
  throw s.error(key, name, "names no inclusion of tissue.inclusions" + (near.empty() ? "" : " (did you mean '" + near + "'?)"),
                names.empty() ? "the scenario has no inclusions" : fmt::format("one of: {}", fmt::join(names, ", ")));
}

// The target: an inclusion marked target: true, or a point inside the tissue.
void checkTarget(Section& s, PlanSpec& p, const Scenario& sc) {
  if (!p.target.empty() && s.has("target_depth"))
    throw s.error("target_depth", "", "is given beside target (an inclusion)", "either target or target_depth");
  if (p.target.empty() && !s.has("target_depth"))
    throw s.error("target", "", "the plan has no target", "target: <inclusion name>, or target_depth (a point)");
  if (!p.target.empty()) {
    const InclusionSpec* I = inclusionNamed(s, "target", p.target, sc);
    if (!I->target)
      throw s.error("target", p.target, "is not marked target: true in tissue.inclusions", "an inclusion with target: true");
    p.target_depth = I->x, p.target_lateral = I->y, p.target_elevation = I->z;
  }
  const TissueSpec& T = sc.tissue;
  const bool inside = p.target_depth <= T.length && std::abs(p.target_lateral) <= T.width / 2 &&
                      std::abs(p.target_elevation) <= T.height / 2;
  if (!inside)
    throw s.error(p.target.empty() ? "target_depth" : "target",
                  fmt::format("({:g}, {:g}, {:g}) mm", p.target_depth * 1e3, p.target_lateral * 1e3, p.target_elevation * 1e3),
                  fmt::format("puts the target outside the {:g} x {:g} x {:g} mm tissue", T.length * 1e3, T.width * 1e3,
                              T.height * 1e3),
                  "a target inside the tissue");
}

// The obstacles and the limits: each contradiction is an error. (The entry window always holds
// insertion.entry_offset, which the reader keeps on the entry face.)
void checkLimits(Section& s, const PlanSpec& p, const Scenario& sc) {
  for (const PlanAvoidSpec& a : p.avoid) {
    inclusionNamed(s, "avoid", a.inclusion, sc);
    if (a.inclusion == p.target)
      throw s.error("avoid", a.inclusion, "is the target", "inclusions other than the target");
  }
  if (p.max_depth > sc.needle.length)
    throw s.error("max_depth", fmt::format("{:g} mm", p.max_depth * 1e3),
                  fmt::format("is longer than the needle ({:g} mm)", sc.needle.length * 1e3), "<= needle.length");
  if (p.max_depth < p.target_depth)
    throw s.error("max_depth", fmt::format("{:g} mm", p.max_depth * 1e3),
                  fmt::format("is shorter than the target's depth ({:g} mm): no path can reach it", p.target_depth * 1e3),
                  "a max_depth beyond the target's depth");
  if (p.choose == "risk" && p.uncertainty.samples == 0)
    throw s.error("choose", "risk", "needs a predicted risk", "uncertainty.samples > 0, or choose: clearance");
}

}  // namespace

std::vector<FieldDoc> planDocs() {
  std::vector<FieldDoc> out = planTable().docs();
  for (auto&& f : avoidTable().docs()) out.push_back(f);
  for (auto&& f : uncertaintyTable().docs()) out.push_back(f);
  return out;
}

void readPlan(Section& s, Scenario& sc) {
  sc.plan.given = true;
  planTable().read(s, sc.plan, sc);
  checkTarget(s, sc.plan, sc);
  checkLimits(s, sc.plan, sc);
}

}  // namespace needlesim::scenario
