// api::Session: the steppable session of the scenario's engine (engines/session.hpp: one
// guard and one adapter per engine for every caller), stepped by the caller.
#include <cmath>

#include <fmt/format.h>

#include "needlesim/api/scenario_impl.hpp"
#include "needlesim/api/translate.hpp"
#include "needlesim/engines/session.hpp"
#include "needlesim/results/inclusion_view.hpp"

namespace needlesim::api {

struct Session::Impl {
  Scenario scenario;
  std::unique_ptr<engines::SteppableSession> session;
  State state;

  explicit Impl(const Scenario& s)
      : scenario(s), session(engines::openSession(detail::ScenarioAccess::typed(scenario))) {
    state.phase = engines::phaseName(0);
  }

  void reset() {
    session->reset();
    state = State{};
    state.phase = engines::phaseName(0);
  }

  void step(const Command& c, double dt) {
    const engines::SessionOutput& o = session->step({c.depth, c.lateral, c.rotation, c.roll, c.tilt, std::nullopt}, dt);
    state.time = session->time();
    state.depth = o.depth;
    state.axial_force = o.axial_force;
    state.lateral_force = o.lateral_force;
    state.stiffness_force = o.stiffness_force;
    state.cutting_force = o.cutting_force;
    state.friction_force = o.friction_force;
    state.tip_x = o.tip.x();
    state.tip_y = o.tip.y();
    state.tip_z = o.tip.z();
    state.tip_deflection = o.tip_deflection;
    state.tip_deflection_z = o.tip_deflection_z;
    state.out_of_plane_force = o.out_of_plane_force;
    state.phase = engines::phaseName(o.phase);
  }

  const engines::SteppableSession& meshed(const std::string& call) const {
    if (!session->hasMesh())
      detail::argumentError(call, "", "engine " + scenario.engine(), "has no tissue mesh or needle shape",
                            "a Session of a scenario with model.engine: realtime2d or realtime3d");
    return *session;
  }
  bool threeD() const { return session->dimension() == 3; }
  std::string geometryFile() const {
    const auto& geometry = detail::ScenarioAccess::typed(scenario).tissue.geometry;
    return geometry ? geometry->file : std::string();
  }
  // Values of the full displacement: dimension x nodes of the FE mesh, 0 for lumped.
  std::size_t displacementValues() const {
    return session->hasMesh() ? static_cast<std::size_t>(session->dimension()) * session->nodeCount() : 0;
  }
};

Session::Session(const Scenario& scenario) : impl_(detail::translated([&] { return std::make_unique<Impl>(scenario); })) {}
Session::~Session() = default;
Session::Session(Session&&) noexcept = default;
Session& Session::operator=(Session&&) noexcept = default;

const State& Session::step(const Command& command, double dt) {
  return detail::translated([&]() -> const State& {
    impl_->step(command, dt);
    return impl_->state;
  });
}

const State& Session::state() const { return impl_->state; }
void Session::reset() { detail::translated([&] { impl_->reset(); }); }
std::string Session::engine() const { return impl_->scenario.engine(); }

Axes Session::axes() const {
  const engines::SessionAxes& a = impl_->session->guard().axes();
  return Axes{a.lateral, a.rotation, a.roll, a.tilt};
}

std::vector<double> Session::nodePositions() const {
  return detail::translated([&] { return impl_->meshed("Session::nodePositions").nodePositions(); });
}

std::vector<double> Session::nodeDisplacements() const {
  return detail::translated([&] {
    const Eigen::VectorXd& u = impl_->meshed("Session::nodeDisplacements").displacement();
    return std::vector<double>(u.data(), u.data() + u.size());
  });
}

std::vector<double> Session::needleShape(int points) const {
  if (points < 2) detail::argumentError("Session::needleShape", "points", std::to_string(points), "is too few", "2 or more points");
  Eigen::MatrixXd shape;
  impl_->meshed("Session::needleShape").needleShape(points, shape);
  return std::vector<double>(shape.data(), shape.data() + shape.size());
}

Surface Session::surface() const {
  return detail::translated([&] {
    Surface out;
    if (impl_->session->hasMesh()) {  // 3D: the block's boundary triangles (outward); 2D: the mesh in z = 0
      const std::vector<double> nodes = impl_->session->nodePositions();
      if (impl_->threeD()) {
        out.vertices = nodes;
      } else {
        out.vertices.reserve(3 * nodes.size() / 2);
        for (std::size_t i = 0; i + 1 < nodes.size(); i += 2) out.vertices.insert(out.vertices.end(), {nodes[i], nodes[i + 1], 0.0});
      }
      out.triangles = impl_->session->surfaceTriangles();
      out.geometry = impl_->geometryFile();
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

std::vector<Inclusion> Session::inclusions() const {
  return detail::translated([&] {
    const std::vector<InclusionSpec>& specs = detail::ScenarioAccess::typed(impl_->scenario).tissue.inclusions;
    std::vector<std::vector<int>> nodes = impl_->session->inclusionNodes();
    nodes.resize(specs.size());  // none without a mesh
    std::vector<Inclusion> out;
    for (std::size_t i = 0; i < specs.size(); ++i) {
      const InclusionSpec& I = specs[i];
      out.push_back({I.name, results::inclusionShapeName(I.shape), I.x, I.y, I.z, I.radius, I.target, std::move(nodes[i])});
    }
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

namespace {
// The viewer's field of a displacement with `dimension` values per node.
void fieldOf(const Eigen::VectorXd& u, int dimension, SurfaceField& field) {
  if (dimension == 3)
    fieldOf3d(u, field);
  else
    fieldOf2d(u, field);
}
}  // namespace

void Session::surfaceField(SurfaceField& field) const {
  nameField(field);
  if (impl_->session->hasMesh())
    fieldOf(impl_->session->displacement(), impl_->session->dimension(), field);
  else
    stillField(field);
}

void Session::snapshotField(FieldSnapshot& snapshot) const {
  if (!snapshot.impl_) snapshot.impl_ = std::make_unique<FieldSnapshot::Impl>();
  FieldSnapshot::Impl& taken = *snapshot.impl_;
  taken.values = impl_->displacementValues();
  impl_->session->saveDisplacement(taken.displacement);
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
    if (!impl_->session->hasMesh()) return stillField(field);
    Eigen::VectorXd u;
    impl_->session->displacementFrom(snapshot.impl_->displacement, u);
    fieldOf(u, impl_->session->dimension(), field);
  });
}

std::vector<double> Session::needleCentreLine(int points) const {
  return detail::translated([&] {
    if (points < 2)
      detail::argumentError("Session::needleCentreLine", "points", std::to_string(points), "is too few", "2 or more points");
    std::vector<double> out;
    out.reserve(3 * points);
    if (impl_->session->hasMesh()) {
      Eigen::MatrixXd shape;
      impl_->session->needleShape(points, shape);
      for (int c = 0; c < points; ++c) out.insert(out.end(), {shape(0, c), shape(1, c), shape.rows() == 3 ? shape(2, c) : 0.0});
      return out;
    }
    // lumped: a straight rigid needle along the insertion axis, its tip at the depth
    const double length = detail::ScenarioAccess::typed(impl_->scenario).needle.length;
    const double tip = impl_->state.depth;
    for (int c = 0; c < points; ++c) out.insert(out.end(), {tip - length * (1.0 - static_cast<double>(c) / (points - 1)), 0.0, 0.0});
    return out;
  });
}

int Session::dimension() const { return impl_->session->dimension(); }

}  // namespace needlesim::api
