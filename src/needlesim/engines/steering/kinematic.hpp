#pragma once
// Nonholonomic kinematic model of a bevel-tip needle in 3D (Webster et al. 2006,
// cited in seed 002 sections 1 and 5.1): the tip frame moves with body twist
// v = e3 (unit insertion), omega = kappa e1 + s e3, where s is the axial spin
// per unit insertion. With omega = kappa e1 the needle curves towards -y of the
// tip frame (the "bevel direction"). Piecewise-constant controls are integrated
// exactly with the SE(3) exponential; a step transform is computed once per
// control phase and then only composed, so the hot loop is a 3x3 product.
#include <span>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace needlesim::steering {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;

struct Pose {
  Mat3 R = Mat3::Identity();  // columns: tip-frame x, y, z (z = needle axis) in world
  Vec3 p = Vec3::Zero();      // m, tip position
  // The direction the needle curves towards (-y of the tip frame).
  Vec3 bevelDirection() const { return -R.col(1); }
};

// One piece of an insertion plan. Applied in order: rotate, then insert.
struct Control {
  double rotate = 0.0;        // rad, axial rotation of the bevel before inserting (a flip = pi)
  double length = 0.0;        // m, insertion length (>= 0)
  double spin = 0.0;          // rad/m, continuous axial spin per unit insertion
  double duty_cycle = 0.0;    // [0, 1]: fraction of each cycle spent spinning one full turn
  double cycle_length = 1e-3; // m of insertion per duty cycle
};

struct KinematicParams {
  double kappa = 0.0;      // 1/m, curvature of the unspun needle (bevel fixed)
  double sample_ds = 1e-3; // m, largest spacing of the recorded tip positions
};

// Exact pose change for a constant body twist (v = e3, omega) over arc length s.
Pose twistExp(const Vec3& omega, double s);

// Integrates the plan from `start`. Writes the start and then one tip position
// per step into `out` (as many as fit) and returns how many it wrote; the final
// pose goes to *end when given. Never allocates.
int simulateKinematic(const KinematicParams& par, const Pose& start, std::span<const Control> plan,
                      std::span<Vec3> out, Pose* end = nullptr);

// Number of positions simulateKinematic would write for this plan.
int kinematicSampleCount(const KinematicParams& par, std::span<const Control> plan);

// Effective curvature of duty-cycled spinning (Minhas et al. 2007):
// kappa_eff = kappa (1 - duty_cycle).
inline double dutyCycleCurvature(double kappa, double duty_cycle) {
  return kappa * (1.0 - duty_cycle);
}
// Duty cycle that realises a commanded curvature 0 <= kappa_cmd <= kappa.
inline double dutyCycleFor(double kappa, double kappa_cmd) {
  return kappa > 0 ? 1.0 - kappa_cmd / kappa : 1.0;
}

}  // namespace needlesim::steering
