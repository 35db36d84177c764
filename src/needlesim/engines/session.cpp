// The steppable session's guard and step; a session opens through its engine's registration
// (engines/registry.cpp, EngineInfo::open).
#include "needlesim/engines/session.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string_view>

#include "needlesim/core/error.hpp"
#include "needlesim/engines/engine.hpp"
#include "needlesim/needle/insertion_frame.hpp"

namespace needlesim::engines {

namespace {

const SourceLocation kSession{"<session>", 0, 0};
constexpr double kQuarter = 0.5 * std::numbers::pi;

[[noreturn]] void refuse(const std::string& argument, const std::string& value, const std::string& problem,
                         const std::string& allowed) {
  throw InputError(kSession, "Session.step(" + argument + ")", value, problem, allowed);
}

// The texts are literals: nothing is composed unless the value is refused.
void requireFinite(const char* argument, double v, const char* allowed) {
  if (!std::isfinite(v)) refuse(argument, fmt::format("{}", v), "must be a finite number", allowed);
}

// An axis the engine does not take must be 0 (the message is composed only for a refusal).
void requireUntaken(const char* argument, double v, bool taken, const std::string& engine) {
  if (taken || v == 0.0) return;
  if (std::string_view(argument) == "tilt")
    refuse(argument, fmt::format("{:g}", v), "tilts the needle out of the insertion plane, which engine " + engine + " cannot",
           "0 (or a realtime3d scenario)");
  refuse(argument, fmt::format("{:g}", v), "the " + engine + " engine moves the needle along its axis only",
         "0 (or a realtime2d scenario)");
}

}  // namespace

std::string phaseName(int phase) {
  static const char* names[] = {"outside", "pressing", "cutting", "inside", "through"};
  return phase >= 0 && phase < 5 ? names[phase] : "unknown";
}

SessionReach reachOf(const Scenario& sc) {
  SessionReach r;
  r.startDepth = sc.insertion.start_depth;
  r.entryDepth = sc.tissue.geometry ? sc.tissue.geometry->entry_depth : 0.0;
  r.maxDepth = sc.needle.length;
  r.width = sc.tissue.width;
  const needle::InsertionFrame frame = needle::InsertionFrame::fromInsertion(sc.insertion);
  const Eigen::Vector3d& e = frame.entry;
  const Eigen::Vector3d& t = frame.axial;
  const Eigen::Vector3d& n = frame.lateral;
  // The axis shifted by l across it meets the entry plane x = 0 at y = y0 + l c.
  const double y0 = e.y() - e.x() * t.y() / t.x(), c = n.y() - n.x() * t.y() / t.x();
  const double a = (-0.5 * r.width - y0) / c, b = (0.5 * r.width - y0) / c;
  r.lateralLo = std::min(a, b);
  r.lateralHi = std::max(a, b);
  const double theta0 = std::atan2(t.y(), t.x());
  r.rotationLo = std::max(-kQuarter, -kQuarter - theta0);
  r.rotationHi = std::min(kQuarter, kQuarter - theta0);
  return r;
}

SessionGuard::SessionGuard(const Scenario& sc, const StepPlan& plan, SessionAxes axes)
    : engine_(sc.model.engine), axes_(axes), reach_(reachOf(sc)), maxTravel_(kMaxTravelPerStep * plan.spacing),
      travelLimit_(fmt::format("{:g} x {}", kMaxTravelPerStep, plan.spacingName)) {}

void SessionGuard::check(const SessionCommand& c, double dt, std::optional<double> previous) const {
  checkFinite(c, dt);
  checkAxes(c);
  checkReach(c);
  checkTravel(c.depth, previous);
  checkVelocity(c, dt, previous);
}

void SessionGuard::checkFinite(const SessionCommand& c, double dt) const {
  requireFinite("depth", c.depth, "a tip depth in m");
  requireFinite("dt", dt, "a time step > 0 s");
  if (!(dt > 0.0)) refuse("dt", fmt::format("{}", dt), "must be > 0", "a time step > 0 s");
  if (c.velocity) requireFinite("velocity", *c.velocity, "a tip velocity in m/s");
  requireFinite("rotation", c.rotation, "an in-plane angle in rad");
  requireFinite("roll", c.roll, "a turn about the needle axis in rad");
  requireFinite("lateral", c.lateral, "a lateral base offset in m");
  requireFinite("tilt", c.tilt, "an out-of-plane angle in rad");
}

// The lumped model is axial (seed 003 section 3.2): its needle only moves along its axis; the
// 2D engine has no out-of-plane direction; the FE engines take the velocity from the depth change.
void SessionGuard::checkAxes(const SessionCommand& c) const {
  requireUntaken("lateral", c.lateral, axes_.lateral, engine_);
  requireUntaken("rotation", c.rotation, axes_.rotation, engine_);
  requireUntaken("roll", c.roll, axes_.roll, engine_);
  requireUntaken("tilt", c.tilt, axes_.tilt, engine_);
  if (c.velocity && !axes_.velocity)
    refuse("velocity", fmt::format("{:g}", *c.velocity), engine_ + " takes the velocity from the depth change over dt",
           "no velocity argument");
}

void SessionGuard::checkReach(const SessionCommand& c) const {
  const SessionReach& r = reach_;
  if (c.depth > r.maxDepth)
    refuse("depth", fmt::format("{:g}", c.depth), "is deeper than the needle is long",
           fmt::format("depth <= needle.length = {:g} m", r.maxDepth));
  if (!(c.lateral > r.lateralLo && c.lateral < r.lateralHi))
    refuse("lateral", fmt::format("{:g}", c.lateral),
           fmt::format("moves the needle's axis off the tissue's entry face, which spans {:g} mm across (tissue width)",
                       1e3 * r.width),
           fmt::format("{:.6g} m < lateral < {:.6g} m", r.lateralLo, r.lateralHi));
  if (!(c.rotation > r.rotationLo && c.rotation < r.rotationHi))
    refuse("rotation", fmt::format("{:g}", c.rotation),
           "turns the needle's axis away from the tissue (it must point in through the entry face)",
           fmt::format("{:.6g} rad < rotation < {:.6g} rad ({:.4g} to {:.4g} deg)", r.rotationLo, r.rotationHi,
                       r.rotationLo * 180 / std::numbers::pi, r.rotationHi * 180 / std::numbers::pi));
  if (!(std::abs(c.tilt) < kQuarter))
    refuse("tilt", fmt::format("{:g}", c.tilt),
           "tilts the needle's axis away from the tissue (it must point in through the entry face)",
           fmt::format("{:.6g} rad < tilt < {:.6g} rad (-90 to 90 deg)", -kQuarter, kQuarter));
}

// The first step starts from insertion.start_depth, where the engine's own run starts;
// before the tissue (depth <= the entry depth) the needle may be placed anywhere.
void SessionGuard::checkTravel(double depth, std::optional<double> previous) const {
  const double e = reach_.entryDepth;
  const double travel =
      previous ? std::abs(depth - *previous) : std::abs(std::max(depth, e) - std::max(reach_.startDepth, e));
  if (!(travel > maxTravel_)) return;
  const std::string from = previous ? fmt::format("in one step (from {:g} mm)", 1e3 * *previous)
                                    : fmt::format("in its first step (a Session starts at insertion.start_depth, {:g} mm; "
                                                  "only before the tissue (depth <= {:g} mm) may it be placed anywhere)",
                                                  1e3 * reach_.startDepth, 1e3 * e);
  refuse("depth", fmt::format("{:g}", depth), fmt::format("moves the tip {:g} mm {}", 1e3 * travel, from),
         fmt::format("at most {:g} mm per step ({}); take smaller steps", 1e3 * maxTravel_, travelLimit_));
}

// The tip velocity a step implies (the depth change over dt, or the given one) must be a
// number: a dt of a few denormals makes it infinite.
void SessionGuard::checkVelocity(const SessionCommand& c, double dt, std::optional<double> previous) const {
  const double change = c.depth - previous.value_or(reach_.startDepth);
  const double v = c.velocity.value_or(change / dt);
  if (!std::isfinite(v))
    refuse("dt", fmt::format("{:g}", dt),
           fmt::format("makes the tip velocity infinite (a depth change of {:g} mm over it)", 1e3 * change),
           "a time step long enough for a finite velocity, such as the scenario's model.time_step");
}

SteppableSession::SteppableSession(const Scenario& sc, const StepPlan& plan, SessionAxes axes)
    : engine_(sc.model.engine), defaultDt_(sc.model.time_step), guard_(sc, plan, axes) {}

const SessionOutput& SteppableSession::step(const SessionCommand& c, double dt) {
  guard_.check(c, dt, previous_);
  advance(c, dt, previous_, out_);
  requireFiniteOutputs(c, dt);
  time_ += dt;
  previous_ = c.depth;
  return out_;
}

void SteppableSession::reset() {
  rebuild();
  out_ = SessionOutput{};
  time_ = 0.0;
  previous_.reset();
}

// A step whose forces or tip are not finite numbers is a SolverError, not a result.
void SteppableSession::requireFiniteOutputs(const SessionCommand& c, double dt) const {
  const SessionOutput& o = out_;
  const double values[] = {o.depth, o.axial_force, o.stiffness_force, o.cutting_force, o.friction_force, o.lateral_force,
                           o.out_of_plane_force, o.tip_deflection, o.tip_deflection_z, o.tip.x(), o.tip.y(), o.tip.z()};
  for (double v : values)
    if (!std::isfinite(v))
      throw SolverError(fmt::format("Session.step: the step to depth {:g} mm over dt = {:g} s gave non-finite forces or "
                                    "tip position; take steps with a longer dt (the scenario's model.time_step is {:g} s)",
                                    1e3 * c.depth, dt, defaultDt_));
}

const Eigen::VectorXd& SteppableSession::displacement() const {
  static const Eigen::VectorXd none;
  return none;
}

void SteppableSession::needleShape(int /*points*/, Eigen::MatrixXd& out) const { out.resize(dimension(), 0); }

std::unique_ptr<SteppableSession> openSession(const Scenario& sc) {
  for (const EngineInfo& e : engineRegistry())
    if (e.open && sc.model.engine == e.name) return e.open(sc);
  throw InputError(sc.where("model.engine"), "model.engine", sc.model.engine,
                   "cannot be stepped by its caller (a Session, needlesim serve): run it with `needlesim run` "
                   "(Python: needlesim.run)",
                   steppableEngines());
}

std::string steppableEngines() {
  std::vector<std::string> names;
  for (const EngineInfo& e : engineRegistry())
    if (e.open) names.push_back(e.name);
  std::string text;
  for (std::size_t i = 0; i < names.size(); ++i)
    text += (i == 0 ? "" : i + 1 == names.size() ? " or " : ", ") + names[i];
  return text;
}

}  // namespace needlesim::engines
