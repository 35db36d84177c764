#pragma once
// The insertion as a scenario gives it (insertion section): entry pose and motion segments.
#include <vector>

namespace needlesim {

struct MotionSegment {
  enum class Kind { Insert, Pause, Retract, Rotate };
  Kind kind = Kind::Insert;
  double speed = 0.0;       // m/s, > 0 (Insert, Retract)
  double to_depth = 0.0;    // m, needle tip depth along its axis at the end (Insert, Retract)
  double duration = 0.0;    // s (Pause; Rotate derived from angle/rate)
  double angle = 0.0;       // rad (Rotate)
  double rate = 0.0;        // rad/s (Rotate; spin rate while inserting)
  bool axial = true;        // Rotate: about the needle axis (bevel) or in the insertion plane (base)
  double duty_cycle = 0.0;  // Insert: fraction of time spinning (0 = no spinning)
};

struct InsertionSpec {
  double entry_angle = 1.5707963267948966;  // rad, between needle and surface (90 deg = normal)
  double entry_offset = 0.0;                // m, entry point from the centre of the entry face
  double start_depth = 0.0;                 // m, tip position at t = 0 (negative = outside)
  double bevel_orientation = 0.0;           // rad, initial axial orientation of the bevel
  std::vector<MotionSegment> segments;
};

}  // namespace needlesim
