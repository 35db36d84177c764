#include "needlesim/insertion/motion_profile.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace needlesim {

MotionProfile::MotionProfile(const InsertionSpec& spec)
    : start_depth_(spec.start_depth), bevel0_(spec.bevel_orientation) {
  double t = 0.0, d = spec.start_depth, ax = spec.bevel_orientation, pl = 0.0, spun = 0.0;
  for (const auto& s : spec.segments) {
    Piece p{t, t, d, 0.0, ax, 0.0, pl, 0.0, 0.0, 0.0, spun};
    switch (s.kind) {
      case MotionSegment::Kind::Insert:
      case MotionSegment::Kind::Retract: {
        double dist = s.to_depth - d;
        p.v = dist > 0 ? s.speed : -s.speed;
        p.t1 = t + std::abs(dist) / s.speed;
        p.spin_rate = s.rate;
        p.duty = s.duty_cycle;
        d = s.to_depth;
        break;
      }
      case MotionSegment::Kind::Pause: p.t1 = t + s.duration; break;
      case MotionSegment::Kind::Rotate:
        p.t1 = t + s.duration;
        if (s.axial) {
          p.axial_rate = std::copysign(s.rate, s.angle);
          ax += s.angle;
        } else {
          p.plane_rate = std::copysign(s.rate, s.angle);
          pl += s.angle;
        }
        break;
    }
    t = p.t1;
    spun += spunIn(p, p.t1 - p.t0);
    pieces_.push_back(p);
  }
  end_time_ = t;
}

MotionState MotionProfile::at(double t) const {
  MotionState m;
  m.depth = start_depth_;
  m.axial_angle = bevel0_;
  if (pieces_.empty() || t < 0.0) return m;
  // Last piece whose start is <= t (later segment wins at a boundary).
  auto it = std::upper_bound(pieces_.begin(), pieces_.end(), t,
                             [](double tt, const Piece& p) { return tt < p.t0; });
  std::size_t i = static_cast<std::size_t>(std::distance(pieces_.begin(), it)) - 1;
  const Piece& p = pieces_[i];
  if (t >= end_time_) {
    const Piece& last = pieces_.back();
    double dt = last.t1 - last.t0;
    m.depth = last.d0 + last.v * dt;
    m.axial_angle = last.axial0 + last.axial_rate * dt;
    m.plane_angle = last.plane0 + last.plane_rate * dt;
    m.segment = static_cast<int>(pieces_.size());
    return m;
  }
  double dt = t - p.t0;
  m.segment = static_cast<int>(i);
  m.depth = p.d0 + p.v * dt;
  m.velocity = p.v;
  m.axial_rate = p.axial_rate;
  m.axial_angle = p.axial0 + p.axial_rate * dt;
  m.plane_rate = p.plane_rate;
  m.plane_angle = p.plane0 + p.plane_rate * dt;
  return m;
}

double MotionProfile::spunIn(const Piece& p, double tau) {
  if (!(p.spin_rate > 0.0) || !(tau > 0.0)) return 0.0;
  if (!(p.duty > 0.0)) return p.spin_rate * tau;
  const double turn = 2.0 * std::numbers::pi / p.spin_rate, cycle = turn / p.duty;
  const double k = std::floor(tau / cycle);
  return 2.0 * std::numbers::pi * k + p.spin_rate * std::min(tau - k * cycle, turn);
}

double MotionProfile::spinAngle(double t) const {
  if (pieces_.empty() || t <= 0.0) return 0.0;
  auto it = std::upper_bound(pieces_.begin(), pieces_.end(), t, [](double tt, const Piece& p) { return tt < p.t0; });
  const Piece& p = *(it - 1);
  return p.spin0 + spunIn(p, std::min(t, p.t1) - p.t0);
}

}  // namespace needlesim
