#pragma once
// The commanded needle pose of a live session and how key/mouse holds or a haptic
// device move it: every axis approaches its target at a bounded rate.
#include "needlesim/needlesim.hpp"

namespace needlesim::live {

// The base pose the user commands (api::Command's fields and the tilt out of the
// insertion plane, which 3D engines take).
struct Pose {
  double depth = 0.0;     // m, tip along the insertion axis from the entry point
  double lateral = 0.0;   // m, base offset across the axis
  double rotation = 0.0;  // rad, turn of the insertion plane
  double tilt = 0.0;      // rad, out of the insertion plane (3D engines)
  double roll = 0.0;      // rad, bevel about the needle axis
};

// Held keys or buttons: each in [-1, 1], a fraction of the axis' top speed.
struct Drive {
  double insert = 0.0, lateral = 0.0, rotate = 0.0, tilt = 0.0, roll = 0.0;
};

// Top speeds and the depth range.
struct MotionLimits {
  double insertSpeed = 5e-3;   // m/s
  double lateralSpeed = 2e-3;  // m/s
  double turnRate = 0.5;       // rad/s for rotation and tilt
  double rollRate = 3.2;       // rad/s
  double minDepth = -5e-3, maxDepth = 0.05;  // m
  double maxLateral = 5e-3;                  // m
  double maxTurn = 0.35;                     // rad, rotation and tilt
};

// Which pose axes an engine takes (the others stay 0).
struct Controls {
  bool lateral = false, rotation = false, tilt = false, roll = false;
};
Controls controlsFor(const api::Axes& axes);

// Moves the target by the drive over dt (clamped to the limits and the controls).
void driveTarget(Pose& target, const Drive& drive, const MotionLimits& limits, const Controls& controls, double dt);
// Clamps a target to the limits and zeroes the axes the engine does not take.
Pose clampTarget(Pose target, const MotionLimits& limits, const Controls& controls);
// Moves `pose` towards `target` at no more than the top speeds over dt.
void approach(Pose& pose, const Pose& target, const MotionLimits& limits, double dt);

// The session's command for a pose (tilt goes to engines that take it).
api::Command commandFor(const Pose& pose);

}  // namespace needlesim::live
