#include "needlesim/engines/step_guard.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>

#include "needlesim/core/error.hpp"
#include "needlesim/engines/engine.hpp"
#include "needlesim/engines/run_cost.hpp"

namespace needlesim {

namespace {

std::string seconds(double s) {
  if (s >= 1.0) return fmt::format("{:.3g} s", s);
  if (s >= 1e-3) return fmt::format("{:.3g} ms", s * 1e3);
  return fmt::format("{:.3g} us", s * 1e6);
}

std::string millimetres(double m) { return fmt::format("{:.3g} mm", m * 1e3); }

std::string speed(double v) { return v >= 1.0 ? fmt::format("{:.3g} m/s", v) : fmt::format("{:.3g} mm/s", v * 1e3); }

// Two significant digits: the estimate holds within a factor 1.5 at best (run_cost.hpp).
std::string wallTime(double s) {
  if (s < 90.0) return fmt::format("{:.2g} s", s);
  if (s < 90.0 * 60.0) return fmt::format("{:.2g} min", s / 60.0);
  if (s < 48.0 * 3600.0) return fmt::format("{:.2g} h", s / 3600.0);
  return fmt::format("{:.2g} days", s / 86400.0);
}

std::string count(double n) {
  return n < 1e5 ? fmt::format("{}", static_cast<long long>(std::llround(n))) : fmt::format("{:.2g}", n);
}

// n rounded up to two significant digits: a budget that admits it.
double roundUp(double n) {
  if (!(n >= 100.0)) return std::ceil(n);
  const double unit = std::pow(10.0, std::floor(std::log10(n)) - 1.0);
  return std::ceil(n / unit) * unit;
}

// A moving segment of the profile: its field, value, duration and speed.
struct Segment {
  std::string field;  // insertion.profile[i].insert.speed
  std::string value;  // "100 m/s"
  double duration = 0.0;
  double speed = 0.0;  // m/s along the axis; 0 for a rotation
};

// The segments that move the needle (insert, retract, rotate); pauses move nothing.
std::vector<Segment> movingSegments(const InsertionSpec& ins) {
  std::vector<Segment> out;
  double depth = ins.start_depth;
  for (std::size_t i = 0; i < ins.segments.size(); ++i) {
    const MotionSegment& m = ins.segments[i];
    const std::string at = fmt::format("insertion.profile[{}]", i);
    switch (m.kind) {
      case MotionSegment::Kind::Insert:
      case MotionSegment::Kind::Retract: {
        const double travel = std::abs(m.to_depth - depth);
        depth = m.to_depth;
        if (!(travel > 0.0)) break;
        const char* kind = m.kind == MotionSegment::Kind::Insert ? "insert" : "retract";
        out.push_back({fmt::format("{}.{}.speed", at, kind), speed(m.speed), travel / m.speed, m.speed});
        break;
      }
      case MotionSegment::Kind::Rotate:
        if (m.duration > 0.0)
          out.push_back({at + ".rotate.rate", fmt::format("{:.3g} deg/s", m.rate * 180.0 / std::numbers::pi),
                         m.duration, 0.0});
        break;
      case MotionSegment::Kind::Pause: break;
    }
  }
  return out;
}

// The longest step that resolves segment s: at most kMaxTravelPerStep x
// spacing of travel per step and at least kMinStepsPerSegment steps.
double longestStep(const StepPlan& plan, const Segment& s) {
  double dt = s.duration / kMinStepsPerSegment;
  if (s.speed > 0.0) dt = std::min(dt, kMaxTravelPerStep * plan.spacing / s.speed);
  return dt;
}

std::string stepAllowed(const StepPlan& plan, double maxStep) {
  return plan.stepAllowed ? plan.stepAllowed(maxStep) : "a time step of at most " + seconds(maxStep);
}

// Why the plan's step does not resolve segment s.
std::string whyUnresolved(const StepPlan& plan, const Segment& s) {
  const std::string step = fmt::format("time step of {} (set by {})", seconds(plan.dt), plan.dtSetBy);
  const double travel = s.speed * plan.dt;
  if (s.speed > 0.0 && travel > kMaxTravelPerStep * plan.spacing)
    return fmt::format("moves the needle {} per {}, more than half {} ({}): the steps would not resolve the "
                       "needle's contact",
                       millimetres(travel), step, plan.spacingName, millimetres(plan.spacing));
  return fmt::format("lasts {} and gets {:.2g} steps at a {}, fewer than the {:g} a motion segment needs",
                     seconds(s.duration), s.duration / plan.dt, step, kMinStepsPerSegment);
}

// What the first segment the step does not resolve allows at this step.
std::string slowerSegment(const StepPlan& plan, const std::vector<Segment>& moving) {
  for (const Segment& s : moving) {
    const double maxStep = longestStep(plan, s);
    if (!(plan.dt > maxStep)) continue;
    if (s.speed > 0.0) return fmt::format("{} at most {}", s.field, speed(s.speed * maxStep / plan.dt));
    return fmt::format("a lower {}", s.field);
  }
  return "a slower profile";
}

// A step longer than the whole motion is the step's fault whatever the speeds
// (e.g. mass scaling 1e12): named by the field that sets it.
void checkStepAgainstMotion(const Scenario& sc, const StepPlan& plan, const std::vector<Segment>& moving) {
  if (moving.empty() || plan.dt < sc.totalDuration()) return;
  double maxStep = plan.dt;
  for (const Segment& s : moving) maxStep = std::min(maxStep, longestStep(plan, s));
  if (!(plan.dt > maxStep)) return;
  throw InputError(sc.where(plan.dtField), plan.dtField, plan.dtValue,
                   fmt::format("{}: the time step {} (set by {}) is longer than the whole {} motion", plan.engine,
                               seconds(plan.dt), plan.dtSetBy, seconds(sc.totalDuration())),
                   fmt::format("{} (for at least {:g} steps per motion segment and at most half {} of travel per "
                               "step), or {}",
                               stepAllowed(plan, maxStep), kMinStepsPerSegment, plan.spacingName,
                               slowerSegment(plan, moving)));
}

// Refuses a moving segment that the plan's time step does not resolve.
void checkSegments(const Scenario& sc, const StepPlan& plan) {
  const std::vector<Segment> moving = movingSegments(sc.insertion);
  checkStepAgainstMotion(sc, plan, moving);
  for (const Segment& s : moving) {
    const double maxStep = longestStep(plan, s);
    if (!(plan.dt > maxStep)) continue;
    const std::string slower =
        s.speed > 0.0 ? fmt::format("at most {} at this step", speed(s.speed * maxStep / plan.dt)) : "a lower rate";
    throw InputError(sc.where(s.field), s.field, s.value, plan.engine + ": " + whyUnresolved(plan, s),
                     slower + ", or " + stepAllowed(plan, maxStep));
  }
}

StepEstimate estimate(const Scenario& sc, const StepPlan& plan) {
  StepEstimate e;
  e.atLeast = plan.adaptive;
  e.steps = plan.dt > 0.0 ? std::ceil(sc.totalDuration() / plan.dt - 1e-9) : plan.steps;
  e.updatesPerStep = plan.updatesPerStep;
  e.updates = plan.updates;
  const double perStep = plan.secondsPerStep + plan.updatesPerStep * plan.secondsPerUpdate;
  if (perStep > 0.0)
    e.seconds = run_cost::kRunSeconds + plan.setupSeconds +
                e.steps * plan.stepGrowth * (perStep / run_cost::speedUp(plan.threads) + plan.serialSecondsPerStep);
  return e;
}

void checkBudget(const Scenario& sc, const StepPlan& plan, const StepEstimate& e) {
  if (!(e.steps > sc.output.max_steps)) return;
  const std::string step =
      plan.dt > 0.0 ? fmt::format(" (time step {}, set by {})", seconds(plan.dt), plan.dtSetBy) : "";
  throw InputError(sc.where("output.max_steps"), "output.max_steps", fmt::format("{:g}", sc.output.max_steps),
                   fmt::format("{}: the run's estimate, {}{}, is more than this budget", plan.engine, e.text(), step),
                   fmt::format("output.max_steps of at least {} to allow it; or fewer steps: {}",
                               count(roundUp(e.steps)), plan.fewerSteps));
}

}  // namespace

StepPlan fixedStepPlan(const Scenario& sc, const std::string& engine) {
  StepPlan p;
  p.engine = engine;
  p.dt = sc.model.time_step;
  p.dtSetBy = p.dtField = "model.time_step";
  p.dtValue = seconds(p.dt);
  p.stepAllowed = [](double maxStep) { return "model.time_step at most " + seconds(maxStep); };
  p.fewerSteps = "a larger model.time_step or a shorter profile";
  return p;
}

std::function<std::string(double)> massScaledStep(const std::string& field, double scaling, double dt,
                                                  const std::string& shorter) {
  return [=](double maxStep) {
    const double most = scaling * (maxStep / dt) * (maxStep / dt);
    if (most >= 1.0) return fmt::format("{} at most {:.2g}", field, most);
    return fmt::format("{} 1 and a step {:.2g} times shorter still ({})", field, std::sqrt(1.0 / most), shorter);
  };
}

std::string StepEstimate::text() const {
  std::string s = (atLeast ? "at least " : "") + count(steps) + (steps == 1.0 ? " step" : " steps");
  if (updatesPerStep > 0.0) s += fmt::format(" x {} {}", count(updatesPerStep), updates);
  if (std::isfinite(seconds)) s += ", about " + wallTime(seconds);
  return s;
}

StepEstimate guardSteps(const Scenario& sc, const StepPlan& plan) {
  if (plan.dt > 0.0) checkSegments(sc, plan);
  const StepEstimate e = estimate(sc, plan);
  checkBudget(sc, plan, e);
  return e;
}

StepEstimate guardAndAnnounce(const Scenario& sc, const StepPlan& plan, ResultSink& sink, const RunOptions& options) {
  const StepEstimate e = guardSteps(sc, plan);
  if (options.progress) {
    fmt::print("estimate: {}\n", e.text());
    std::fflush(stdout);  // seen before a long set-up, also where the output goes to a file or a pipe
  }
  sink.note(fmt::format("Estimated before the run: {} (output.max_steps {:g}).", e.text(), sc.output.max_steps));
  return e;
}

void warnZeroForce(const Scenario& sc, double peakForce, ResultSink& sink) {
  if (peakForce != 0.0 || !(sc.maxDepth() > 0.0)) return;
  sink.warning(fmt::format(
      "the force on the needle stayed 0 N although the tip reached {} inside the tissue; the steps did not "
      "resolve the contact (check the time step and the speeds of insertion.profile).",
      millimetres(sc.maxDepth())));
}

}  // namespace needlesim
