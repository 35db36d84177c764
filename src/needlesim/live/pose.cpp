#include "needlesim/live/pose.hpp"

#include <algorithm>
#include <cmath>

namespace needlesim::live {

namespace {
double towards(double from, double to, double maxStep) { return from + std::clamp(to - from, -maxStep, maxStep); }
double unit(double v) { return std::isfinite(v) ? std::clamp(v, -1.0, 1.0) : 0.0; }
}  // namespace

Controls controlsFor(const api::Axes& axes) { return {axes.lateral, axes.rotation, axes.tilt, axes.roll}; }

Pose clampTarget(Pose t, const MotionLimits& l, const Controls& c) {
  t.depth = std::clamp(t.depth, l.minDepth, l.maxDepth);
  t.lateral = c.lateral ? std::clamp(t.lateral, -l.maxLateral, l.maxLateral) : 0.0;
  t.rotation = c.rotation ? std::clamp(t.rotation, -l.maxTurn, l.maxTurn) : 0.0;
  t.tilt = c.tilt ? std::clamp(t.tilt, -l.maxTurn, l.maxTurn) : 0.0;
  t.roll = c.roll ? t.roll : 0.0;
  return t;
}

void driveTarget(Pose& t, const Drive& d, const MotionLimits& l, const Controls& c, double dt) {
  t.depth += unit(d.insert) * l.insertSpeed * dt;
  t.lateral += unit(d.lateral) * l.lateralSpeed * dt;
  t.rotation += unit(d.rotate) * l.turnRate * dt;
  t.tilt += unit(d.tilt) * l.turnRate * dt;
  t.roll += unit(d.roll) * l.rollRate * dt;
  t = clampTarget(t, l, c);
}

void approach(Pose& p, const Pose& t, const MotionLimits& l, double dt) {
  p.depth = towards(p.depth, t.depth, l.insertSpeed * dt);
  p.lateral = towards(p.lateral, t.lateral, l.lateralSpeed * dt);
  p.rotation = towards(p.rotation, t.rotation, l.turnRate * dt);
  p.tilt = towards(p.tilt, t.tilt, l.turnRate * dt);
  p.roll = towards(p.roll, t.roll, l.rollRate * dt);
}

// The tilt goes to the engines that take it (realtime3d); controlsFor holds it at 0 for the others.
api::Command commandFor(const Pose& p) { return api::Command{p.depth, p.lateral, p.rotation, p.roll, p.tilt}; }

}  // namespace needlesim::live
