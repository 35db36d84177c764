#pragma once
// The insertion profile as a function of time: tip depth along the needle
// axis, its velocity, and the rotations, for any engine to sample.
#include <vector>

#include "needlesim/insertion/insertion_spec.hpp"

namespace needlesim {

struct MotionState {
  double depth = 0.0;          // m, tip position along the needle axis from the entry point
  double velocity = 0.0;       // m/s, d(depth)/dt
  double axial_angle = 0.0;    // rad, bevel orientation about the needle axis
  double axial_rate = 0.0;     // rad/s
  double plane_angle = 0.0;    // rad, in-plane rotation of the base relative to the entry direction
  double plane_rate = 0.0;     // rad/s
  int segment = -1;            // index of the active segment (-1 before the first, n after the last)
};

// Steps of `dt` between recorded samples for a sampling `interval` (0 = every step).
inline long long outputStride(double interval, double dt) {
  if (!(interval > 0.0)) return 1;
  const long long n = static_cast<long long>(interval / dt + 0.5);
  return n < 1 ? 1 : n;
}

class MotionProfile {
 public:
  explicit MotionProfile(const InsertionSpec& spec);
  double duration() const { return end_time_; }
  // Piecewise-constant velocity; at a segment boundary the later segment wins.
  MotionState at(double t) const;
  // rad, the bevel's turn by the insert segments' spinning up to time t (not in `at`): a spin at
  // `spin_rate` throughout, or duty cycling (a fraction duty_cycle of the time spinning): per
  // cycle one full turn at spin_rate, then the rest of the cycle with the bevel fixed, as engine
  // kinematic does (Minhas et al. 2007).
  double spinAngle(double t) const;

 private:
  struct Piece {
    double t0, t1, d0, v, axial0, axial_rate, plane0, plane_rate, spin_rate, duty;
    double spin0 = 0.0;  // rad, spun before the piece
  };
  static double spunIn(const Piece& p, double tau);
  std::vector<Piece> pieces_;
  double end_time_ = 0.0;
  double start_depth_ = 0.0;
  double bevel0_ = 0.0;
};

}  // namespace needlesim
