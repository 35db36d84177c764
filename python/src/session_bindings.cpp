// needlesim._core.Session: an engine stepped by the caller (a haptic loop, a planner), through
// its steppable session (engines/session.hpp: lumped, realtime2d, realtime3d), with the same
// guard and messages as the C++ API and needlesim serve; the tissue mesh and the needle shape
// exist for the FE engines, the inclusions (results/inclusion_view.hpp) for every engine.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <optional>

#include "bindings.hpp"
#include "needlesim/core/error.hpp"
#include "needlesim/engines/session.hpp"
#include "needlesim/insertion/motion_profile.hpp"
#include "needlesim/results/inclusion_view.hpp"

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

// A tissue.inclusions entry as the C++ API gives it to a viewer (api::Inclusion), and where it is
// at the session's current step (results::inclusionAtStep, as the trainer's readout).
struct SessionInclusion {
  std::string name, shape;             // shape: sphere, cylinder or mesh
  std::array<double, 3> centre{};      // m, reference centre, tissue frame
  double radius = 0.0;                 // m
  bool target = false;
  std::vector<int> region;             // the mesh nodes of its material (none for lumped)
  std::array<double, 3> displaced_centre{};  // m, centre + the mean displacement of region
  std::optional<double> miss, miss_from_axis;  // m, targets of a stepped FE session
};

// x y z per column of a dim x n block (z = 0 for 2D).
std::vector<double> threeD(const double* data, Eigen::Index dim, Eigen::Index n) {
  std::vector<double> out(3 * static_cast<std::size_t>(n), 0.0);
  for (Eigen::Index i = 0; i < n; ++i)
    for (Eigen::Index c = 0; c < dim; ++c) out[static_cast<std::size_t>(3 * i + c)] = data[dim * i + c];
  return out;
}

// needle_shape's point count: 2 to a million (a bound on the memory it takes).
void checkShapePoints(int count) {
  if (count < 2 || count > 1000000)
    throw InputError(kPython, "Session.needle_shape(count)", std::to_string(count),
                     count < 2 ? "must be at least 2" : "is more points than a centre line needs",
                     "a number of points from 2 to 1000000");
}

// n x k array from a column-major k x n block (k values per point).
template <class T>
py::array_t<T> pointsOf(const T* data, std::size_t size, py::ssize_t k) {
  py::array_t<T> out({static_cast<py::ssize_t>(size) / k, k});
  std::copy(data, data + size, out.mutable_data());
  return out;
}

// needlesim.Session: the engine's steppable session (engines/session.hpp), whose guard refuses
// what every other caller's refuses, with the same messages.
class PySession {
 public:
  explicit PySession(const PyScenario& s)
      : name_(s.scenario.name), inclusions_(s.scenario.tissue.inclusions), session_(engines::openSession(s.scenario)) {}

  SessionStep step(double depth, std::optional<double> dt, std::optional<double> velocity, double rotation, double roll,
                   double lateral, double tilt) {
    const engines::SessionOutput& o =
        session_->step({depth, lateral, rotation, roll, tilt, velocity}, dt.value_or(session_->defaultDt()));
    SessionStep s;
    s.time = session_->time();
    s.depth = o.depth;
    s.force_total = o.axial_force;
    s.force_stiffness = o.stiffness_force;
    s.force_cutting = o.cutting_force;
    s.force_friction = o.friction_force;
    s.force_lateral = o.lateral_force;
    s.tip_position = {o.tip.x(), o.tip.y(), o.tip.z()};
    s.tip_deflection = o.tip_deflection;
    s.phase = engines::phaseName(o.phase);
    s.punctured_now = o.punctured_now;
    s.torque = o.torque;
    s.tip_load = o.tip_load;
    if (session_->dimension() == 3) {
      s.force_out_of_plane = o.out_of_plane_force;
      s.tip_deflection_z = o.tip_deflection_z;
    }
    return s;
  }
  const std::string& engine() const { return session_->engine(); }
  const std::string& name() const { return name_; }
  double defaultDt() const { return session_->defaultDt(); }
  double time() const { return session_->time(); }
  std::optional<double> depth() const { return session_->depth(); }

  // The FE engines only; the lumped model has no tissue mesh.
  py::array_t<double> referencePoints() const {
    const std::vector<double> x = meshed("points").nodePositions();
    return pointsOf(x.data(), x.size(), session_->dimension());
  }
  py::array_t<double> displacement() const {
    const Eigen::VectorXd& u = meshed("displacement").displacement();
    return pointsOf(u.data(), static_cast<std::size_t>(u.size()), session_->dimension());
  }
  py::array_t<int> cells() const {
    const std::vector<int> c = meshed("cells").cells();  // quadrilaterals or tetrahedra
    return pointsOf(c.data(), c.size(), 4);
  }
  py::array_t<int> surface() const {
    if (session_->dimension() != 3)
      throw InputError(kPython, "Session.surface", engine(), "has no tetrahedral tissue", "a Session of a realtime3d scenario");
    const std::vector<int> t = session_->surfaceTriangles();
    return pointsOf(t.data(), t.size(), 3);
  }
  py::array_t<double> needleShape(int count) const {
    const engines::SteppableSession& s = meshed("needle_shape");
    checkShapePoints(count);
    Eigen::MatrixXd shape;
    s.needleShape(count, shape);
    return pointsOf(shape.data(), static_cast<std::size_t>(shape.size()), shape.rows());
  }
  std::vector<SessionInclusion> inclusions() const;

 private:
  const engines::SteppableSession& meshed(const std::string& what) const {
    if (!session_->hasMesh())
      throw InputError(kPython, "Session." + what, engine(), "the lumped engine has no tissue mesh or needle shape",
                       "a Session of a realtime2d scenario");
    return *session_;
  }

  std::string name_;
  std::vector<InclusionSpec> inclusions_;
  std::unique_ptr<engines::SteppableSession> session_;
};

// The FE engines' displacement and, once stepped, needle centre line (41 points, as the C++
// API's needleCentreLine) in 3D; lumped: none of either.
std::vector<SessionInclusion> PySession::inclusions() const {
  std::vector<std::vector<int>> nodes = session_->inclusionNodes();
  nodes.resize(inclusions_.size());
  std::vector<double> u, needle;
  if (session_->hasMesh()) {
    const Eigen::VectorXd& d = session_->displacement();
    const int dim = session_->dimension();
    u = threeD(d.data(), dim, d.size() / dim);
    if (session_->depth()) {
      Eigen::MatrixXd shape;
      session_->needleShape(41, shape);
      needle = threeD(shape.data(), shape.rows(), shape.cols());
    }
  }
  std::vector<SessionInclusion> out;
  for (std::size_t i = 0; i < inclusions_.size(); ++i) {
    const InclusionSpec& I = inclusions_[i];
    const results::InclusionAtStep at = results::inclusionAtStep({I.x, I.y, I.z}, I.target, nodes[i], u, needle);
    SessionInclusion v{I.name, results::inclusionShapeName(I.shape), {I.x, I.y, I.z}, I.radius, I.target,
                       std::move(nodes[i]), {at.centre.x(), at.centre.y(), at.centre.z()}, std::nullopt, std::nullopt};
    if (at.miss) {
      v.miss = at.miss->distance;
      v.miss_from_axis = at.miss->fromAxis;
    }
    out.push_back(std::move(v));
  }
  return out;
}

std::string sessionRepr(const PySession& s) {
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

  py::class_<PySession>(m, "Session",
                          "A realtime2d or lumped scenario's engine, stepped by the caller (docs/python.md). "
                          "realtime2d also gives its tissue mesh (points, cells), node displacements and needle shape.")
      .def(py::init<const PyScenario&>(), py::arg("scenario"))
      .def_property_readonly("engine", &PySession::engine)
      .def_property_readonly("dt", &PySession::defaultDt)
      .def_property_readonly("time", &PySession::time)
      .def_property_readonly("depth", &PySession::depth)
      .def("__repr__", &sessionRepr)
      .def("step", &PySession::step, py::arg("depth"), py::arg("dt") = py::none(), py::arg("velocity") = py::none(),
           py::arg("rotation") = 0.0, py::arg("roll") = 0.0, py::arg("lateral") = 0.0, py::arg("tilt") = 0.0,
           "Advance to tip depth [m] (along the reference axis from the entry point) over dt [s] (default: the "
           "scenario's model.time_step); rotation [rad] in the plane, roll [rad] about the axis from the bevel "
           "orientation and lateral [m] base offset (realtime2d, realtime3d); tilt [rad] out of the plane (realtime3d); velocity [m/s] (lumped; default: depth change / dt). "
           "Returns a SessionStep. Bad arguments, a depth change beyond the step guard (from the first step, which starts at "
           "insertion.start_depth) and poses outside the tissue's reach raise needlesim.InputError (docs/python.md).")
      .def_property_readonly("points", &PySession::referencePoints, "tissue nodes, n x 2 (realtime3d: n x 3) [m] (centred frame)")
      .def_property_readonly("displacement", &PySession::displacement, "node displacements, n x 2 (realtime3d: n x 3) [m]")
      .def_property_readonly("cells", &PySession::cells, "quadrilaterals (realtime3d: tetrahedra), m x 4 node indices")
      .def_property_readonly("surface", &PySession::surface, "realtime3d: boundary triangles of the tissue, k x 3 node indices")
      .def("needle_shape", &PySession::needleShape, py::arg("count") = 41,
           "the needle's centre line from base to tip, count x 2 (realtime3d: count x 3) [m]")
      .def_property_readonly("inclusions", &PySession::inclusions,
                             "tissue.inclusions as a viewer shows them, at the current step: a list of Inclusion");

  auto point3 = [](const std::array<double, 3>& p) { return py::array_t<double>(3, p.data()); };
  py::class_<SessionInclusion>(m, "Inclusion",
                               "A tissue.inclusions entry (centres in the tissue frame [m]) and where it is at the "
                               "session's step (docs/python.md)")
      .def_readonly("name", &SessionInclusion::name)
      .def_readonly("shape", &SessionInclusion::shape)
      .def_property_readonly("centre", [point3](const SessionInclusion& I) { return point3(I.centre); })
      .def_readonly("radius", &SessionInclusion::radius)
      .def_readonly("target", &SessionInclusion::target)
      .def_property_readonly("region", [](const SessionInclusion& I) { return py::array_t<int>(static_cast<py::ssize_t>(I.region.size()), I.region.data()); })
      .def_property_readonly("displaced_centre", [point3](const SessionInclusion& I) { return point3(I.displaced_centre); })
      .def_readonly("miss", &SessionInclusion::miss)
      .def_readonly("miss_from_axis", &SessionInclusion::miss_from_axis)
      .def("__repr__", [](const SessionInclusion& I) {
        return fmt::format("<Inclusion {} '{}'{}: radius={:.6g} mm{}>", I.shape, I.name, I.target ? " (target)" : "",
                           1e3 * I.radius, I.miss ? fmt::format(" miss={:.6g} mm", 1e3 * *I.miss) : std::string());
      });

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
