// The lumped force model stepped by its caller: the tip along the straight axis of the shared
// frame, at the commanded depth (seed 003 section 3.2: a rigid needle, axial forces only).
#include "needlesim/engines/lumped/lumped_session.hpp"

#include "needlesim/engines/lumped/lumped_engine.hpp"
#include "needlesim/forces/lumped_model.hpp"
#include "needlesim/needle/insertion_frame.hpp"

namespace needlesim::engines {

namespace {

class LumpedSession final : public SteppableSession {
 public:
  explicit LumpedSession(const Scenario& sc)
      : SteppableSession(sc, lumpedStepPlan(sc), SessionAxes{.velocity = true}),
        initial_(sc.tissue, sc.needle, sc.insertion.entry_angle, sc.model.lumped.relaxation_time),
        model_(initial_),
        frame_(needle::InsertionFrame::fromInsertion(sc.insertion)) {}

  int dimension() const override { return 2; }

 private:
  void advance(const SessionCommand& c, double dt, std::optional<double> previous, SessionOutput& o) override {
    const double v = c.velocity.value_or(previous ? (c.depth - *previous) / dt : 0.0);
    const forces::ForceBreakdown f = model_.step(c.depth, v, dt);
    o.depth = c.depth;
    o.axial_force = f.total();
    o.stiffness_force = f.stiffness;
    o.cutting_force = f.cutting;
    o.friction_force = f.friction;
    o.tip = frame_.onAxis(c.depth);
    o.phase = static_cast<int>(f.phase);
    o.punctured_now = f.punctured_now;
  }
  void rebuild() override { model_ = initial_; }

  forces::LumpedForceModel initial_, model_;  // as built, and stepped
  needle::InsertionFrame frame_;
};

}  // namespace

std::unique_ptr<SteppableSession> openLumpedSession(const Scenario& scenario) {
  return std::make_unique<LumpedSession>(scenario);
}

}  // namespace needlesim::engines
