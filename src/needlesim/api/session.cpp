// api::Session: the realtime2d engine's Session or the lumped force model, stepped by the caller.
#include <cmath>
#include <optional>

#include <fmt/format.h>

#include "needlesim/api/scenario_impl.hpp"
#include "needlesim/api/translate.hpp"
#include "needlesim/engines/realtime2d/realtime2d_engine.hpp"
#include "needlesim/engines/realtime3d/realtime3d_engine.hpp"
#include "needlesim/forces/lumped_model.hpp"

namespace needlesim::api {

namespace {

constexpr const char* kSteppable = "lumped, realtime2d or realtime3d (model.engine)";

// The phases of both models share their numbering (forces::Phase, realtime2d::Phase).
std::string phaseName(int phase) {
  static const char* names[] = {"outside", "pressing", "cutting", "inside", "through"};
  return phase >= 0 && phase < 5 ? names[phase] : "unknown";
}

void requireFinite(const std::string& argument, double v, const std::string& allowed) {
  if (!std::isfinite(v)) detail::argumentError("Session::step", argument, fmt::format("{}", v), "must be a finite number", allowed);
}

void checkCommand(const Command& c, double dt) {
  requireFinite("command.depth", c.depth, "a tip depth in m");
  requireFinite("command.lateral", c.lateral, "a lateral base offset in m");
  requireFinite("command.rotation", c.rotation, "a rotation of the insertion plane in rad");
  requireFinite("command.roll", c.roll, "a roll of the bevel in rad");
  requireFinite("command.tilt", c.tilt, "a tilt out of the insertion plane in rad");
  requireFinite("dt", dt, "a time step > 0 s");
  if (!(dt > 0.0)) detail::argumentError("Session::step", "dt", fmt::format("{}", dt), "must be > 0", "a time step > 0 s");
}

}  // namespace

struct Session::Impl {
  Scenario scenario;
  std::optional<realtime2d::Session> fe;            // engine realtime2d
  std::optional<forces::LumpedForceModel> lumped;  // engine lumped
  std::optional<realtime3d::Session> fe3;           // engine realtime3d
  double previousDepth = 0.0;
  bool stepped = false;
  State state;

  explicit Impl(const Scenario& s) : scenario(s) { build(); }

  void build() {
    const needlesim::Scenario& sc = detail::ScenarioAccess::typed(scenario);
    if (sc.model.engine == "realtime2d") {
      fe.emplace(engines::realtime2dConfig(sc));
    } else if (sc.model.engine == "realtime3d") {
      fe3.emplace(engines::realtime3dConfig(sc));
    } else if (sc.model.engine == "lumped") {
      lumped.emplace(sc.tissue, sc.needle, sc.insertion.entry_angle, sc.model.lumped.relaxation_time);
    } else {
      throw needlesim::InputError(sc.where("model.engine"), "model.engine", sc.model.engine,
                                  "cannot be stepped live (needlesim serve, a Session): run it with `needlesim run`",
                                  kSteppable);
    }
    state = State{};
    state.phase = phaseName(0);
    stepped = false;
  }

  // The state both FE sessions' step results give alike.
  template <class StepResult>
  void feState(const StepResult& o) {
    state.depth = o.depth;
    state.axial_force = o.axial_force;
    state.lateral_force = o.lateral_force;
    state.stiffness_force = o.stiffness_force;
    state.cutting_force = o.cutting_force;
    state.friction_force = o.friction_force;
    state.tip_x = o.tip_position.x();
    state.tip_y = o.tip_position.y();
    state.phase = phaseName(static_cast<int>(o.phase));
  }

  void stepFe3(const Command& c, double dt) {
    const realtime3d::StepResult& o = fe3->step(fe3->poseAtDepth(c.depth, c.lateral, 0.0, c.rotation, c.tilt, c.roll), dt);
    feState(o);
    state.out_of_plane_force = o.out_of_plane_force;
    state.tip_z = o.tip_position.z();
    state.tip_deflection = o.tip_deflection[0];
    state.tip_deflection_z = o.tip_deflection[1];
  }

  void stepFe(const Command& c, double dt) {
    if (c.tilt != 0.0)
      detail::argumentError("Session::step", "command.tilt", fmt::format("{}", c.tilt),
                            "tilts the needle out of the insertion plane, which the 2D engine cannot",
                            "0 for realtime2d; a scenario with model.engine: realtime3d");
    const realtime2d::StepResult& o = fe->step(fe->poseAtDepth(c.depth, c.lateral, c.rotation, c.roll), dt);
    feState(o);
    state.tip_deflection = o.tip_deflection;
  }

  void stepLumped(const Command& c, double dt) {
    if (c.lateral != 0.0 || c.rotation != 0.0 || c.roll != 0.0 || c.tilt != 0.0)
      detail::argumentError("Session::step", "command", fmt::format("lateral {}, rotation {}, roll {}", c.lateral, c.rotation, c.roll),
                            "steers the needle, which the lumped model (a straight rigid needle) cannot",
                            "0 for lumped; a scenario with model.engine: realtime2d for lateral, rotation and roll");
    const double velocity = stepped ? (c.depth - previousDepth) / dt : 0.0;
    const forces::ForceBreakdown f = lumped->step(c.depth, velocity, dt);
    state.depth = c.depth;
    state.axial_force = f.total();
    state.lateral_force = 0.0;
    state.stiffness_force = f.stiffness;
    state.cutting_force = f.cutting;
    state.friction_force = f.friction;
    state.tip_x = c.depth;
    state.tip_y = 0.0;
    state.tip_deflection = 0.0;
    state.phase = phaseName(static_cast<int>(f.phase));
  }

  const realtime2d::Session& feOnly(const std::string& call) const {
    if (!fe)
      detail::argumentError(call, "", "engine " + scenario.engine(), "has no tissue mesh or needle shape",
                            "a Session of a scenario with model.engine: realtime2d or realtime3d");
    return *fe;
  }
  bool threeD() const { return fe3.has_value(); }
  // Values of the full displacement: dimension x nodes of the FE mesh, 0 for lumped.
  std::size_t displacementValues() const {
    if (fe3) return fe3->mesh().X.size();
    if (fe) return 2 * static_cast<std::size_t>(fe->mesh().nodeCount());
    return 0;
  }
};

Session::Session(const Scenario& scenario) : impl_(detail::translated([&] { return std::make_unique<Impl>(scenario); })) {}
Session::~Session() = default;
Session::Session(Session&&) noexcept = default;
Session& Session::operator=(Session&&) noexcept = default;

const State& Session::step(const Command& command, double dt) {
  return detail::translated([&]() -> const State& {
    checkCommand(command, dt);
    if (impl_->fe3)
      impl_->stepFe3(command, dt);
    else if (impl_->fe)
      impl_->stepFe(command, dt);
    else
      impl_->stepLumped(command, dt);
    impl_->state.time += dt;
    impl_->previousDepth = command.depth;
    impl_->stepped = true;
    return impl_->state;
  });
}

const State& Session::state() const { return impl_->state; }
void Session::reset() { detail::translated([&] { impl_->build(); }); }
std::string Session::engine() const { return impl_->scenario.engine(); }

std::vector<double> Session::nodePositions() const {
  if (impl_->threeD()) {
    std::vector<double> x = impl_->fe3->mesh().X;
    for (std::size_t i = 0; i < x.size(); ++i) x[i] -= impl_->fe3->cornerShift()[static_cast<Eigen::Index>(i % 3)];
    return x;
  }
  const realtime2d::Session& fe = impl_->feOnly("Session::nodePositions");
  const Eigen::Matrix2Xd centred = fe.mesh().nodes.colwise() - fe.cornerShift();
  return std::vector<double>(centred.data(), centred.data() + centred.size());
}

std::vector<double> Session::nodeDisplacements() const {
  const Eigen::VectorXd& u = impl_->threeD() ? impl_->fe3->displacement() : impl_->feOnly("Session::nodeDisplacements").displacement();
  return std::vector<double>(u.data(), u.data() + u.size());
}

std::vector<double> Session::needleShape(int points) const {
  if (points < 2) detail::argumentError("Session::needleShape", "points", std::to_string(points), "is too few", "2 or more points");
  if (impl_->threeD()) {
    Eigen::Matrix3Xd shape(3, points);
    impl_->fe3->needleShape(points, shape);
    return std::vector<double>(shape.data(), shape.data() + shape.size());
  }
  const realtime2d::Session& fe = impl_->feOnly("Session::needleShape");
  Eigen::Matrix2Xd shape(2, points);
  fe.needleShape(points, shape);
  return std::vector<double>(shape.data(), shape.data() + shape.size());
}

Surface Session::surface() const {
  return detail::translated([&] {
    Surface out;
    if (impl_->threeD()) {  // the tetrahedral block's boundary triangles (outward) over all its nodes
      out.vertices = nodePositions();
      const Eigen::Matrix3Xi& T = impl_->fe3->tissue().surfaceTriangles();
      out.triangles.assign(T.data(), T.data() + T.size());
      return out;
    }
    if (impl_->fe) {
      const realtime2d::Mesh& mesh = impl_->fe->mesh();
      const Eigen::Matrix2Xd centred = mesh.nodes.colwise() - impl_->fe->cornerShift();
      out.vertices.reserve(3 * centred.cols());
      for (Eigen::Index i = 0; i < centred.cols(); ++i) out.vertices.insert(out.vertices.end(), {centred(0, i), centred(1, i), 0.0});
      out.triangles.reserve(6 * mesh.quads.cols());
      for (Eigen::Index e = 0; e < mesh.quads.cols(); ++e) {
        const auto q = mesh.quads.col(e);
        out.triangles.insert(out.triangles.end(), {q(0), q(1), q(2)});
        if (q(3) != q(2)) out.triangles.insert(out.triangles.end(), {q(0), q(2), q(3)});  // not a collapsed triangle
      }
      return out;
    }
    // lumped: the block's mid-plane from the entry face (x = 0) to the exit face
    const needlesim::TissueSpec& t = detail::ScenarioAccess::typed(impl_->scenario).tissue;
    const double w = 0.5 * t.width;
    out.vertices = {0.0, -w, 0.0, t.length, -w, 0.0, t.length, w, 0.0, 0.0, w, 0.0};
    out.triangles = {0, 1, 2, 0, 2, 3};
    return out;
  });
}

namespace {

// The viewer's field of a 3D displacement (x y z per node) and its magnitude.
void fieldOf3d(const Eigen::VectorXd& u, SurfaceField& field) {
  const std::size_t n = static_cast<std::size_t>(u.size() / 3);
  field.displacement.assign(u.data(), u.data() + u.size());
  field.scalar.resize(n);
  for (std::size_t i = 0; i < n; ++i) field.scalar[i] = u.segment<3>(static_cast<Eigen::Index>(3 * i)).norm();
}

// The viewer's field of a 2D displacement (x y per node), in z = 0.
void fieldOf2d(const Eigen::VectorXd& u, SurfaceField& field) {
  const std::size_t n = static_cast<std::size_t>(u.size() / 2);
  field.displacement.assign(3 * n, 0.0);
  field.scalar.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    field.displacement[3 * i] = u[2 * i];
    field.displacement[3 * i + 1] = u[2 * i + 1];
    field.scalar[i] = std::hypot(u[2 * i], u[2 * i + 1]);
  }
}

// The lumped model's plane (4 vertices) does not move.
void stillField(SurfaceField& field) {
  field.displacement.assign(12, 0.0);
  field.scalar.assign(4, 0.0);
}

void nameField(SurfaceField& field) {
  field.scalarName = "|u|";
  field.scalarUnit = "m";
}

}  // namespace

struct FieldSnapshot::Impl {
  realtime::DisplacementState displacement;
  std::size_t values = 0;  // the taking session's displacement values (dimension x nodes; 0 for lumped)
};

FieldSnapshot::FieldSnapshot() = default;
FieldSnapshot::~FieldSnapshot() = default;
FieldSnapshot::FieldSnapshot(FieldSnapshot&&) noexcept = default;
FieldSnapshot& FieldSnapshot::operator=(FieldSnapshot&&) noexcept = default;

void Session::surfaceField(SurfaceField& field) const {
  nameField(field);
  if (impl_->fe3)
    fieldOf3d(impl_->fe3->displacement(), field);
  else if (impl_->fe)
    fieldOf2d(impl_->fe->displacement(), field);
  else
    stillField(field);
}

void Session::snapshotField(FieldSnapshot& snapshot) const {
  if (!snapshot.impl_) snapshot.impl_ = std::make_unique<FieldSnapshot::Impl>();
  FieldSnapshot::Impl& taken = *snapshot.impl_;
  taken.values = impl_->displacementValues();
  if (impl_->fe3)
    impl_->fe3->saveDisplacement(taken.displacement);
  else if (impl_->fe)
    impl_->fe->saveDisplacement(taken.displacement);
}

void Session::surfaceField(const FieldSnapshot& snapshot, SurfaceField& field) const {
  detail::translated([&] {
    if (snapshot.empty())
      detail::argumentError("Session::surfaceField", "snapshot", "empty", "holds no state", "a snapshot filled by snapshotField");
    if (snapshot.impl_->values != impl_->displacementValues())
      detail::argumentError("Session::surfaceField", "snapshot", fmt::format("{} displacement values", snapshot.impl_->values),
                            fmt::format("was filled on another mesh than the simulated one ({} values)", impl_->displacementValues()),
                            "a snapshot filled by snapshotField on a Session of the same scenario");
    nameField(field);
    Eigen::VectorXd u;
    if (impl_->fe3) {
      impl_->fe3->displacementFrom(snapshot.impl_->displacement, u);
      fieldOf3d(u, field);
    } else if (impl_->fe) {
      impl_->fe->displacementFrom(snapshot.impl_->displacement, u);
      fieldOf2d(u, field);
    } else {
      stillField(field);
    }
  });
}

std::vector<double> Session::needleCentreLine(int points) const {
  return detail::translated([&] {
    if (points < 2)
      detail::argumentError("Session::needleCentreLine", "points", std::to_string(points), "is too few", "2 or more points");
    if (impl_->threeD()) return needleShape(points);  // already x y z per point
    std::vector<double> out;
    out.reserve(3 * points);
    if (impl_->fe) {
      Eigen::Matrix2Xd shape(2, points);
      impl_->fe->needleShape(points, shape);
      for (int c = 0; c < points; ++c) out.insert(out.end(), {shape(0, c), shape(1, c), 0.0});
      return out;
    }
    // lumped: a straight rigid needle along the insertion axis, its tip at the depth
    const double length = detail::ScenarioAccess::typed(impl_->scenario).needle.length;
    const double tip = impl_->state.depth;
    for (int c = 0; c < points; ++c) out.insert(out.end(), {tip - length * (1.0 - static_cast<double>(c) / (points - 1)), 0.0, 0.0});
    return out;
  });
}

int Session::dimension() const { return impl_->threeD() ? 3 : 2; }

}  // namespace needlesim::api
