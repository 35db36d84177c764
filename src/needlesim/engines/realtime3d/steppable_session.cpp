// realtime3d::Session stepped by its caller: the commanded pose (with its tilt out of the
// plane) through poseAtDepth; the tet block, its boundary triangles, displacement and needle.
#include "needlesim/engines/realtime3d/steppable_session.hpp"

#include <optional>

#include "needlesim/engines/realtime3d/realtime3d_engine.hpp"

namespace needlesim::engines {

namespace {

class Realtime3dSession final : public SteppableSession {
 public:
  explicit Realtime3dSession(const Scenario& sc)
      : SteppableSession(sc, realtime3dStepPlan(sc),
                         SessionAxes{.lateral = true, .rotation = true, .roll = true, .tilt = true}),
        config_(realtime3dConfig(sc)), inclusions_(sc.tissue.inclusions.size()) {
    rebuild();
  }

  int dimension() const override { return 3; }
  bool hasMesh() const override { return true; }
  std::size_t nodeCount() const override { return fe_->mesh().X.size() / 3; }
  std::vector<double> nodePositions() const override {
    std::vector<double> x = fe_->mesh().X;
    for (std::size_t i = 0; i < x.size(); ++i) x[i] -= fe_->cornerShift()[static_cast<Eigen::Index>(i % 3)];
    return x;
  }
  const Eigen::VectorXd& displacement() const override { return fe_->displacement(); }
  std::vector<int> cells() const override { return fe_->mesh().conn; }
  std::vector<int> surfaceTriangles() const override {
    const Eigen::Matrix3Xi& t = fe_->tissue().surfaceTriangles();
    return {t.data(), t.data() + t.size()};
  }
  void needleShape(int points, Eigen::MatrixXd& out) const override {
    Eigen::Matrix3Xd shape(3, points);
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
    const realtime3d::StepResult& o = fe_->step(fe_->poseAtDepth(c.depth, c.lateral, 0.0, c.rotation, c.tilt, c.roll), dt);
    s.depth = o.depth;
    s.axial_force = o.axial_force;
    s.stiffness_force = o.stiffness_force;
    s.cutting_force = o.cutting_force;
    s.friction_force = o.friction_force;
    s.lateral_force = o.lateral_force;
    s.out_of_plane_force = o.out_of_plane_force;
    s.tip = o.tip_position;
    s.tip_deflection = o.tip_deflection[0];
    s.tip_deflection_z = o.tip_deflection[1];
    s.phase = static_cast<int>(o.phase);
    s.punctured_now = o.punctured_now;
    s.tip_load = o.tip_load[0];
  }
  void rebuild() override { fe_.emplace(config_); }  // its mesh and factorisation

  realtime3d::SessionConfig config_;
  std::optional<realtime3d::Session> fe_;
  std::size_t inclusions_;  // tissue.inclusions: the first material regions
};

}  // namespace

std::unique_ptr<SteppableSession> openRealtime3dSession(const Scenario& scenario) {
  return std::make_unique<Realtime3dSession>(scenario);
}

}  // namespace needlesim::engines
