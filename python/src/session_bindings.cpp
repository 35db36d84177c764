// needlesim._core.Session: the real-time engines stepped by the caller (a haptic
// loop, a planner). One class for all: `realtime2d` (2D FE tissue and needle,
// realtime2d::Session), `realtime3d` (tetrahedral block, realtime3d::Session) and `lumped`
// (forces::LumpedForceModel); the tissue mesh and the needle shape exist for the FE engines.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <numbers>
#include <optional>

#include "bindings.hpp"
#include "needlesim/core/error.hpp"
#include "needlesim/engines/lumped/lumped_engine.hpp"
#include "needlesim/engines/realtime2d/realtime2d_engine.hpp"
#include "needlesim/engines/realtime2d/session.hpp"
#include "needlesim/engines/realtime3d/realtime3d_engine.hpp"
#include "needlesim/forces/lumped_model.hpp"
#include "needlesim/insertion/motion_profile.hpp"
#include "needlesim/needle/insertion_frame.hpp"

namespace py = pybind11;

namespace needlesim::python {
namespace {

const SourceLocation kPython{"<python>", 0, 0};

// One step's outputs, the same names as forces.csv (docs/results.md).
struct SessionStep {
  double time = 0.0;             // s, session time (sum of the steps' dt)
  double depth = 0.0;            // m, tip along the reference axis from the entry point
  double force_total = 0.0;      // N, axial force resisting insertion
  double force_stiffness = 0.0;  // N, eq 3.16 part
  double force_cutting = 0.0;    // N, eq 3.24 part
  double force_friction = 0.0;   // N, eq 3.23 part
  double force_lateral = 0.0;    // N, tissue force along the frame's lateral direction (0 in lumped)
  std::array<double, 3> tip_position{0.0, 0.0, 0.0};  // m, shared frame (x depth, y, z)
  double tip_deflection = 0.0;   // m, elastic lateral tip deflection (0 in lumped)
  std::string phase = "outside";
  bool punctured_now = false;
  std::optional<double> torque, tip_load;  // realtime2d: N m about the base, N bevel load
  std::optional<double> force_out_of_plane, tip_deflection_z;  // realtime3d: N, m along the frame's outOfPlane
};

template <class PhaseEnum>
std::string phaseName(PhaseEnum p) {
  switch (static_cast<int>(p)) {
    case 0: return "outside";
    case 1: return "pressing";
    case 2: return "cutting";
    case 3: return "inside";
    case 4: return "through";
  }
  return "unknown";
}

// The arguments of Session.step after the engine-neutral checks.
struct StepArgs {
  double depth, dt;
  std::optional<double> velocity;
  double rotation, roll, lateral;
  double tilt = 0.0;  // rad, out of the insertion plane (realtime3d)
};

// Where a Session's needle may go (docs/python.md "Sessions"): the tip no deeper than the
// needle is long, the base offset across the axis and the angles that keep the needle's
// axis pointing into the tissue through its entry face.
struct Reach {
  double startDepth = 0.0;  // m, insertion.start_depth: where a Session's needle starts
  double entryDepth = 0.0;  // m, tip depth where the axis meets the tissue
  double maxDepth = 0.0;    // m, needle.length
  double lateralLo = 0.0, lateralHi = 0.0;    // m, open range of the base offset
  double rotationLo = 0.0, rotationHi = 0.0;  // rad, open range of the in-plane turn
  double width = 0.0;                         // m, the entry face across the insertion plane
};

Reach reachOf(const Scenario& sc) {
  constexpr double kQuarter = 0.5 * std::numbers::pi;
  Reach r;
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

class SessionBase {
 public:
  SessionBase(const Scenario& sc, double maxTravel, std::string travelLimit)
      : engine_(sc.model.engine), name_(sc.name), dt_(sc.model.time_step), maxTravel_(maxTravel),
        travelLimit_(std::move(travelLimit)), reach_(reachOf(sc)) {}
  virtual ~SessionBase() = default;

  SessionStep step(double depth, std::optional<double> dt, std::optional<double> velocity, double rotation, double roll,
                   double lateral, double tilt) {
    StepArgs a{depth, dt.value_or(dt_), velocity, rotation, roll, lateral, tilt};
    checkArgs(a);
    SessionStep s = advance(a);
    requireFiniteOutputs(s, a);
    time_ += a.dt;
    s.time = time_;
    last_ = a.depth;
    return s;
  }
  const std::string& engine() const { return engine_; }
  const std::string& name() const { return name_; }
  double defaultDt() const { return dt_; }
  double time() const { return time_; }
  std::optional<double> depth() const { return last_; }

  // realtime2d only; the lumped model has no tissue mesh.
  virtual py::array_t<double> referencePoints() const { throw noMesh("points"); }
  virtual py::array_t<double> displacement() const { throw noMesh("displacement"); }
  virtual py::array_t<int> cells() const { throw noMesh("cells"); }
  virtual py::array_t<double> needleShape(int) const { throw noMesh("needle_shape"); }
  virtual py::array_t<int> surface() const {
    throw InputError(kPython, "Session.surface", engine_, "has no tetrahedral tissue", "a Session of a realtime3d scenario");
  }

 protected:
  virtual SessionStep advance(const StepArgs& a) = 0;
  InputError noMesh(const std::string& what) const {
    return InputError(kPython, "Session." + what, engine_, "the lumped engine has no tissue mesh or needle shape",
                      "a Session of a realtime2d scenario");
  }
  std::optional<double> last_;  // depth of the previous step

 private:
  // Finite numbers, dt > 0, a pose within the tissue's reach, and a tip that moves no more
  // than the engine's step guard allows, from the first step on.
  void checkArgs(const StepArgs& a) const {
    requireFinite("Session.step", "depth", a.depth, "a tip depth in m");
    requirePositive("Session.step", "dt", a.dt, "a time step > 0 s");
    if (a.velocity) requireFinite("Session.step", "velocity", *a.velocity, "a tip velocity in m/s");
    requireFinite("Session.step", "rotation", a.rotation, "an in-plane angle in rad");
    requireFinite("Session.step", "roll", a.roll, "a turn about the needle axis in rad");
    requireFinite("Session.step", "lateral", a.lateral, "a lateral base offset in m");
    requireFinite("Session.step", "tilt", a.tilt, "an out-of-plane angle in rad");
    if (a.tilt != 0.0 && engine_ != "realtime3d")
      throw InputError(kPython, "Session.step(tilt)", fmt::format("{:g}", a.tilt),
                       "tilts the needle out of the insertion plane, which engine " + engine_ + " cannot",
                       "0 (or a realtime3d scenario)");
    checkReach(a);
    checkTravel(a.depth);
    checkVelocity(a);
  }

  // The tip velocity a step implies (the depth change over dt, or the lumped model's given one)
  // must be a number: a dt of a few denormals makes it infinite.
  void checkVelocity(const StepArgs& a) const {
    const double change = a.depth - last_.value_or(reach_.startDepth);
    const double v = a.velocity.value_or(change / a.dt);
    if (!std::isfinite(v))
      throw InputError(kPython, "Session.step(dt)", fmt::format("{:g}", a.dt),
                       fmt::format("makes the tip velocity infinite (a depth change of {:g} mm over it)", 1e3 * change),
                       "a time step long enough for a finite velocity, such as the scenario's model.time_step");
  }

  // A step whose forces or tip are not finite numbers is a SolverError, not a result.
  void requireFiniteOutputs(const SessionStep& s, const StepArgs& a) const {
    const double values[] = {s.depth, s.force_total, s.force_stiffness, s.force_cutting, s.force_friction,
                             s.force_lateral, s.tip_deflection, s.tip_position[0], s.tip_position[1], s.tip_position[2]};
    for (double v : values)
      if (!std::isfinite(v))
        throw SolverError(fmt::format("Session.step: the step to depth {:g} mm over dt = {:g} s gave non-finite forces or "
                                      "tip position; take steps with a longer dt (the scenario's model.time_step is {:g} s)",
                                      1e3 * a.depth, a.dt, dt_));
  }

  void checkReach(const StepArgs& a) const {
    const Reach& r = reach_;
    if (a.depth > r.maxDepth)
      throw InputError(kPython, "Session.step(depth)", fmt::format("{:g}", a.depth), "is deeper than the needle is long",
                       fmt::format("depth <= needle.length = {:g} m", r.maxDepth));
    if (!(a.lateral > r.lateralLo && a.lateral < r.lateralHi))
      throw InputError(kPython, "Session.step(lateral)", fmt::format("{:g}", a.lateral),
                       fmt::format("moves the needle's axis off the tissue's entry face, which spans {:g} mm across "
                                   "(tissue width)",
                                   1e3 * r.width),
                       fmt::format("{:.6g} m < lateral < {:.6g} m", r.lateralLo, r.lateralHi));
    if (!(a.rotation > r.rotationLo && a.rotation < r.rotationHi))
      throw InputError(kPython, "Session.step(rotation)", fmt::format("{:g}", a.rotation),
                       "turns the needle's axis away from the tissue (it must point in through the entry face)",
                       fmt::format("{:.6g} rad < rotation < {:.6g} rad ({:.4g} to {:.4g} deg)", r.rotationLo,
                                   r.rotationHi, r.rotationLo * 180 / std::numbers::pi, r.rotationHi * 180 / std::numbers::pi));
    constexpr double kQuarter = 0.5 * std::numbers::pi;
    if (!(std::abs(a.tilt) < kQuarter))
      throw InputError(kPython, "Session.step(tilt)", fmt::format("{:g}", a.tilt),
                       "tilts the needle's axis away from the tissue (it must point in through the entry face)",
                       fmt::format("{:.6g} rad < tilt < {:.6g} rad (-90 to 90 deg)", -kQuarter, kQuarter));
  }

  // The first step starts from insertion.start_depth, where the engine's own run starts;
  // before the tissue (depth <= the entry depth) the needle may be placed anywhere.
  void checkTravel(double depth) const {
    const double e = reach_.entryDepth;
    const double travel =
        last_ ? std::abs(depth - *last_) : std::abs(std::max(depth, e) - std::max(reach_.startDepth, e));
    if (!(travel > maxTravel_)) return;
    const std::string from = last_ ? fmt::format("in one step (from {:g} mm)", 1e3 * *last_)
                                   : fmt::format("in its first step (a Session starts at insertion.start_depth, {:g} mm; "
                                                 "only before the tissue (depth <= {:g} mm) may it be placed anywhere)",
                                                 1e3 * reach_.startDepth, 1e3 * e);
    throw InputError(kPython, "Session.step(depth)", fmt::format("{:g}", depth),
                     fmt::format("moves the tip {:g} mm {}", 1e3 * travel, from),
                     fmt::format("at most {:g} mm per step ({}); take smaller steps", 1e3 * maxTravel_, travelLimit_));
  }

  std::string engine_, name_;
  double dt_, maxTravel_, time_ = 0.0;
  std::string travelLimit_;
  Reach reach_;
};

std::string travelText(const StepPlan& p) { return fmt::format("{:g} x {}", kMaxTravelPerStep, p.spacingName); }

class LumpedSession final : public SessionBase {
 public:
  LumpedSession(const Scenario& sc, const StepPlan& plan)
      : SessionBase(sc, kMaxTravelPerStep * plan.spacing, travelText(plan)),
        model_(sc.tissue, sc.needle, sc.insertion.entry_angle, sc.model.lumped.relaxation_time),
        frame_(needle::InsertionFrame::fromInsertion(sc.insertion)) {}

 private:
  SessionStep advance(const StepArgs& a) override {
    requireAxial("rotation", a.rotation);
    requireAxial("roll", a.roll);
    requireAxial("lateral", a.lateral);
    const double v = a.velocity.value_or(last_ ? (a.depth - *last_) / a.dt : 0.0);
    const forces::ForceBreakdown f = model_.step(a.depth, v, a.dt);
    SessionStep s;
    s.depth = a.depth;
    s.force_total = f.total();
    s.force_stiffness = f.stiffness;
    s.force_cutting = f.cutting;
    s.force_friction = f.friction;
    const Eigen::Vector3d tip = frame_.onAxis(a.depth);
    s.tip_position = {tip.x(), tip.y(), tip.z()};
    s.phase = phaseName(f.phase);
    s.punctured_now = f.punctured_now;
    return s;
  }
  // The lumped model is axial (seed 003 section 3.2): the needle only moves along its axis.
  void requireAxial(const std::string& arg, double v) const {
    if (v != 0.0)
      throw InputError(kPython, "Session.step(" + arg + ")", fmt::format("{:g}", v),
                       "the lumped engine moves the needle along its axis only", "0 (or a realtime2d scenario)");
  }

  forces::LumpedForceModel model_;
  needle::InsertionFrame frame_;
};

// needle_shape's point count: 2 to a million (a bound on the memory it takes).
void checkShapePoints(int count) {
  if (count < 2 || count > 1000000)
    throw InputError(kPython, "Session.needle_shape(count)", std::to_string(count),
                     count < 2 ? "must be at least 2" : "is more points than a centre line needs",
                     "a number of points from 2 to 1000000");
}

// The FE sessions take the velocity from the depth change over dt.
void refuseVelocity(const StepArgs& a, const std::string& engine) {
  if (a.velocity)
    throw InputError(kPython, "Session.step(velocity)", fmt::format("{:g}", *a.velocity),
                     engine + " takes the velocity from the depth change over dt", "no velocity argument");
}

// What both FE sessions' step results give alike.
template <class StepResult>
SessionStep feStep(const StepResult& o) {
  SessionStep s;
  s.depth = o.depth;
  s.force_total = o.axial_force;
  s.force_stiffness = o.stiffness_force;
  s.force_cutting = o.cutting_force;
  s.force_friction = o.friction_force;
  s.force_lateral = o.lateral_force;
  s.phase = phaseName(o.phase);
  s.punctured_now = o.punctured_now;
  return s;
}

class Realtime2dSession final : public SessionBase {
 public:
  Realtime2dSession(const Scenario& sc, const StepPlan& plan)
      : SessionBase(sc, kMaxTravelPerStep * plan.spacing, travelText(plan)), session_(engines::realtime2dConfig(sc)) {}

  py::array_t<double> referencePoints() const override {
    const Eigen::Matrix2Xd centred = session_.mesh().nodes.colwise() - session_.cornerShift();
    return rowsOf(centred);
  }
  py::array_t<double> displacement() const override {
    const Eigen::VectorXd& u = session_.displacement();
    py::array_t<double> out({static_cast<py::ssize_t>(u.size() / 2), py::ssize_t{2}});
    std::copy(u.data(), u.data() + u.size(), out.mutable_data());
    return out;
  }
  py::array_t<int> cells() const override {
    const Eigen::Matrix4Xi& q = session_.mesh().quads;
    py::array_t<int> out({static_cast<py::ssize_t>(q.cols()), py::ssize_t{4}});
    std::copy(q.data(), q.data() + q.size(), out.mutable_data());  // column-major 4 x n = row-major n x 4
    return out;
  }
  py::array_t<double> needleShape(int count) const override {
    checkShapePoints(count);
    Eigen::Matrix2Xd shape;
    session_.needleShape(count, shape);
    return rowsOf(shape);
  }

 private:
  // A 2 x n matrix as an n x 2 array.
  static py::array_t<double> rowsOf(const Eigen::Matrix2Xd& m) {
    py::array_t<double> out({static_cast<py::ssize_t>(m.cols()), py::ssize_t{2}});
    std::copy(m.data(), m.data() + m.size(), out.mutable_data());
    return out;
  }

  SessionStep advance(const StepArgs& a) override {
    refuseVelocity(a, "realtime2d");
    const realtime2d::BasePose pose = session_.poseAtDepth(a.depth, a.lateral, a.rotation, a.roll);
    const realtime2d::StepResult& o = session_.step(pose, a.dt);
    SessionStep s = feStep(o);
    s.tip_position = {o.tip_position.x(), o.tip_position.y(), 0.0};
    s.tip_deflection = o.tip_deflection;
    s.torque = o.torque;
    s.tip_load = o.tip_load;
    return s;
  }

  realtime2d::Session session_;
};

// n x k array from a column-major k x n block (k values per point).
template <class T>
py::array_t<T> pointsOf(const T* data, std::size_t size, py::ssize_t k) {
  py::array_t<T> out({static_cast<py::ssize_t>(size) / k, k});
  std::copy(data, data + size, out.mutable_data());
  return out;
}

class Realtime3dSession final : public SessionBase {
 public:
  Realtime3dSession(const Scenario& sc, const StepPlan& plan)
      : SessionBase(sc, kMaxTravelPerStep * plan.spacing, travelText(plan)), session_(engines::realtime3dConfig(sc)) {}

  py::array_t<double> referencePoints() const override {
    std::vector<double> x = session_.mesh().X;
    for (std::size_t i = 0; i < x.size(); ++i) x[i] -= session_.cornerShift()[static_cast<Eigen::Index>(i % 3)];
    return pointsOf(x.data(), x.size(), 3);
  }
  py::array_t<double> displacement() const override {
    const Eigen::VectorXd& u = session_.displacement();
    return pointsOf(u.data(), static_cast<std::size_t>(u.size()), 3);
  }
  py::array_t<int> cells() const override {
    const auto& c = session_.mesh().conn;
    return pointsOf(c.data(), c.size(), 4);
  }
  py::array_t<int> surface() const override {
    const Eigen::Matrix3Xi& T = session_.tissue().surfaceTriangles();
    return pointsOf(T.data(), static_cast<std::size_t>(T.size()), 3);
  }
  py::array_t<double> needleShape(int count) const override {
    checkShapePoints(count);
    Eigen::Matrix3Xd shape;
    session_.needleShape(count, shape);
    return pointsOf(shape.data(), static_cast<std::size_t>(shape.size()), 3);
  }

 private:
  SessionStep advance(const StepArgs& a) override {
    refuseVelocity(a, "realtime3d");
    const realtime3d::StepResult& o =
        session_.step(session_.poseAtDepth(a.depth, a.lateral, 0.0, a.rotation, a.tilt, a.roll), a.dt);
    SessionStep s = feStep(o);
    s.force_out_of_plane = o.out_of_plane_force;
    s.tip_position = {o.tip_position.x(), o.tip_position.y(), o.tip_position.z()};
    s.tip_deflection = o.tip_deflection[0];
    s.tip_deflection_z = o.tip_deflection[1];
    s.tip_load = o.tip_load[0];
    return s;
  }

  realtime3d::Session session_;
};

std::unique_ptr<SessionBase> openSession(const PyScenario& s) {
  const Scenario& sc = s.scenario;
  if (sc.model.engine == "realtime2d")
    return std::make_unique<Realtime2dSession>(sc, engines::realtime2dStepPlan(sc));
  if (sc.model.engine == "realtime3d")
    return std::make_unique<Realtime3dSession>(sc, engines::realtime3dStepPlan(sc));
  if (sc.model.engine == "lumped") return std::make_unique<LumpedSession>(sc, engines::lumpedStepPlan(sc));
  throw InputError(sc.where("model.engine"), "model.engine", sc.model.engine,
                   "cannot be stepped by the caller (needlesim.Session)",
                   "realtime2d, realtime3d or lumped; other engines run with needlesim.run");
}

std::string sessionRepr(const SessionBase& s) {
  return fmt::format("<Session {} '{}': t={:.6g} s, {}>", s.engine(), s.name(), s.time(),
                     s.depth() ? fmt::format("depth={:.6g} mm", 1e3 * *s.depth()) : std::string("not stepped yet"));
}

std::string stepRepr(const SessionStep& s) {
  return fmt::format("<SessionStep t={:.6g} s depth={:.6g} mm force_total={:.6g} N force_lateral={:.6g} N "
                     "tip_deflection={:.6g} mm phase={}>",
                     s.time, 1e3 * s.depth, s.force_total, s.force_lateral, 1e3 * s.tip_deflection, s.phase);
}

// The scenario's insertion profile at time t, as Session.step takes it.
struct MotionSample {
  double time, depth, velocity, rotation, roll;
};

}  // namespace

py::object motionAt(const PyScenario& s, double t) {
  requireFinite("Scenario.motion_at", "t", t, "a time in s");
  const MotionState m = MotionProfile(s.scenario.insertion).at(t);
  return py::cast(MotionSample{t, m.depth, m.velocity, m.plane_angle, m.axial_angle - s.scenario.insertion.bevel_orientation});
}

void bindSessions(py::module_& m) {
  py::class_<SessionStep>(m, "SessionStep", "One Session.step: forces [N], tip [m], phase (forces.csv's names)")
      .def_readonly("time", &SessionStep::time)
      .def_readonly("depth", &SessionStep::depth)
      .def_readonly("force_total", &SessionStep::force_total)
      .def_readonly("force_stiffness", &SessionStep::force_stiffness)
      .def_readonly("force_cutting", &SessionStep::force_cutting)
      .def_readonly("force_friction", &SessionStep::force_friction)
      .def_readonly("force_lateral", &SessionStep::force_lateral)
      .def_property_readonly("tip_position",
                             [](const SessionStep& s) { return py::array_t<double>(3, s.tip_position.data()); })
      .def_readonly("tip_deflection", &SessionStep::tip_deflection)
      .def_readonly("phase", &SessionStep::phase)
      .def_readonly("punctured_now", &SessionStep::punctured_now)
      .def_readonly("torque", &SessionStep::torque)
      .def_readonly("tip_load", &SessionStep::tip_load)
      .def_readonly("force_out_of_plane", &SessionStep::force_out_of_plane)
      .def_readonly("tip_deflection_z", &SessionStep::tip_deflection_z)
      .def("__repr__", &stepRepr);

  py::class_<SessionBase>(m, "Session",
                          "A realtime2d or lumped scenario's engine, stepped by the caller (docs/python.md). "
                          "realtime2d also gives its tissue mesh (points, cells), node displacements and needle shape.")
      .def(py::init(&openSession), py::arg("scenario"))
      .def_property_readonly("engine", &SessionBase::engine)
      .def_property_readonly("dt", &SessionBase::defaultDt)
      .def_property_readonly("time", &SessionBase::time)
      .def_property_readonly("depth", &SessionBase::depth)
      .def("__repr__", &sessionRepr)
      .def("step", &SessionBase::step, py::arg("depth"), py::arg("dt") = py::none(), py::arg("velocity") = py::none(),
           py::arg("rotation") = 0.0, py::arg("roll") = 0.0, py::arg("lateral") = 0.0, py::arg("tilt") = 0.0,
           "Advance to tip depth [m] (along the reference axis from the entry point) over dt [s] (default: the "
           "scenario's model.time_step); rotation [rad] in the plane, roll [rad] about the axis from the bevel "
           "orientation and lateral [m] base offset (realtime2d, realtime3d); tilt [rad] out of the plane (realtime3d); velocity [m/s] (lumped; default: depth change / dt). "
           "Returns a SessionStep. Bad arguments, a depth change beyond the step guard (from the first step, which starts at "
           "insertion.start_depth) and poses outside the tissue's reach raise needlesim.InputError (docs/python.md).")
      .def_property_readonly("points", &SessionBase::referencePoints, "tissue nodes, n x 2 (realtime3d: n x 3) [m] (centred frame)")
      .def_property_readonly("displacement", &SessionBase::displacement, "node displacements, n x 2 (realtime3d: n x 3) [m]")
      .def_property_readonly("cells", &SessionBase::cells, "quadrilaterals (realtime3d: tetrahedra), m x 4 node indices")
      .def_property_readonly("surface", &SessionBase::surface, "realtime3d: boundary triangles of the tissue, k x 3 node indices")
      .def("needle_shape", &SessionBase::needleShape, py::arg("count") = 41,
           "the needle's centre line from base to tip, count x 2 (realtime3d: count x 3) [m]");

  py::class_<MotionSample>(m, "MotionSample")
      .def_readonly("time", &MotionSample::time)
      .def_readonly("depth", &MotionSample::depth)
      .def_readonly("velocity", &MotionSample::velocity)
      .def_readonly("rotation", &MotionSample::rotation)
      .def_readonly("roll", &MotionSample::roll)
      .def("__repr__", [](const MotionSample& s) {
        return fmt::format("<MotionSample t={:.6g} s depth={:.6g} mm velocity={:.6g} mm/s rotation={:.6g} rad roll={:.6g} rad>",
                           s.time, 1e3 * s.depth, 1e3 * s.velocity, s.rotation, s.roll);
      });
}

}  // namespace needlesim::python
