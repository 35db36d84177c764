// realtime2d::Session stepped by its caller: the commanded pose through poseAtDepth, its step
// result as the session's output; the quad mesh, displacement and needle in the centred frame.
#include "needlesim/engines/realtime2d/steppable_session.hpp"

#include <optional>

#include "needlesim/engines/realtime2d/realtime2d_engine.hpp"

namespace needlesim::engines {

namespace {

class Realtime2dSession final : public SteppableSession {
 public:
  explicit Realtime2dSession(const Scenario& sc)
      : SteppableSession(sc, realtime2dStepPlan(sc), SessionAxes{.lateral = true, .rotation = true, .roll = true}),
        config_(realtime2dConfig(sc)), inclusions_(sc.tissue.inclusions.size()) {
    rebuild();
  }

  int dimension() const override { return 2; }
  bool hasMesh() const override { return true; }
  std::size_t nodeCount() const override { return static_cast<std::size_t>(fe_->mesh().nodeCount()); }
  std::vector<double> nodePositions() const override {
    const Eigen::Matrix2Xd centred = fe_->mesh().nodes.colwise() - fe_->cornerShift();
    return {centred.data(), centred.data() + centred.size()};
  }
  const Eigen::VectorXd& displacement() const override { return fe_->displacement(); }
  std::vector<int> cells() const override {
    const Eigen::Matrix4Xi& q = fe_->mesh().quads;
    return {q.data(), q.data() + q.size()};
  }
  std::vector<int> surfaceTriangles() const override {
    const Eigen::Matrix4Xi& quads = fe_->mesh().quads;
    std::vector<int> out;
    out.reserve(6 * quads.cols());
    for (Eigen::Index e = 0; e < quads.cols(); ++e) {
      const auto q = quads.col(e);
      out.insert(out.end(), {q(0), q(1), q(2)});
      if (q(3) != q(2)) out.insert(out.end(), {q(0), q(2), q(3)});  // not a collapsed triangle
    }
    return out;
  }
  void needleShape(int points, Eigen::MatrixXd& out) const override {
    Eigen::Matrix2Xd shape(2, points);
    fe_->needleShape(points, shape);
    out = shape;
  }
  std::vector<std::vector<int>> inclusionNodes() const override {
    std::vector<std::vector<int>> nodes(inclusions_);
    for (std::size_t i = 0; i < inclusions_; ++i) nodes[i] = fe_->tissue().regionNodes(i);
    return nodes;
  }
  void saveDisplacement(realtime::DisplacementState& state) const override { fe_->saveDisplacement(state); }
  void displacementFrom(const realtime::DisplacementState& state, Eigen::VectorXd& u) const override {
    fe_->displacementFrom(state, u);
  }

 private:
  void advance(const SessionCommand& c, double dt, std::optional<double>, SessionOutput& s) override {
    const realtime2d::StepResult& o = fe_->step(fe_->poseAtDepth(c.depth, c.lateral, c.rotation, c.roll), dt);
    s.depth = o.depth;
    s.axial_force = o.axial_force;
    s.stiffness_force = o.stiffness_force;
    s.cutting_force = o.cutting_force;
    s.friction_force = o.friction_force;
    s.lateral_force = o.lateral_force;
    s.tip = {o.tip_position.x(), o.tip_position.y(), 0.0};
    s.tip_deflection = o.tip_deflection;
    s.phase = static_cast<int>(o.phase);
    s.punctured_now = o.punctured_now;
    s.torque = o.torque;
    s.tip_load = o.tip_load;
  }
  void rebuild() override { fe_.emplace(config_); }  // its mesh and factorisation

  realtime2d::SessionConfig config_;
  std::optional<realtime2d::Session> fe_;
  std::size_t inclusions_;  // tissue.inclusions: the first material regions
};

}  // namespace

std::unique_ptr<SteppableSession> openRealtime2dSession(const Scenario& scenario) {
  return std::make_unique<Realtime2dSession>(scenario);
}

}  // namespace needlesim::engines
