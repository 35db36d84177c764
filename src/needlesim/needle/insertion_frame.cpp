#include "needlesim/needle/insertion_frame.hpp"

#include <cmath>

namespace needlesim::needle {

namespace {
// cos and sin without the round-off of a right angle: a normal insertion runs exactly along x,
// so that mesh nodes and material points on the needle's plane lie on it, not 1e-17 to one side.
double exact(double v) { return std::abs(v) < 1e-15 ? 0.0 : v; }
}  // namespace

InsertionFrame InsertionFrame::fromInsertion(const InsertionSpec& insertion) {
  InsertionFrame f;
  const double th = insertion.entry_angle, c = exact(std::cos(th)), s = exact(std::sin(th));
  f.entry = Eigen::Vector3d(0.0, insertion.entry_offset, 0.0);
  f.axial = Eigen::Vector3d(s, c, 0.0);
  f.lateral = Eigen::Vector3d(-c, s, 0.0);
  f.outOfPlane = Eigen::Vector3d::UnitZ();
  f.bevelOrientation = insertion.bevel_orientation;
  return f;
}

Eigen::Vector3d InsertionFrame::bevelSide(double roll) const {
  const double a = bevelOrientation + roll;
  return std::cos(a) * lateral + std::sin(a) * outOfPlane;
}

double InsertionFrame::bevelSign(double roll) const {
  return std::cos(bevelOrientation + roll) >= 0.0 ? 1.0 : -1.0;
}

}  // namespace needlesim::needle
