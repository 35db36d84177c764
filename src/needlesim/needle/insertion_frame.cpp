#include "needlesim/needle/insertion_frame.hpp"

#include <cmath>

namespace needlesim::needle {

InsertionFrame InsertionFrame::fromInsertion(const InsertionSpec& insertion) {
  InsertionFrame f;
  const double th = insertion.entry_angle;
  f.entry = Eigen::Vector3d(0.0, insertion.entry_offset, 0.0);
  f.axial = Eigen::Vector3d(std::sin(th), std::cos(th), 0.0);
  f.lateral = Eigen::Vector3d(-std::cos(th), std::sin(th), 0.0);
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

Eigen::Vector3d cornerShift(const TissueSpec& tissue) {
  return {0.0, 0.5 * tissue.width, 0.5 * tissue.height};
}

}  // namespace needlesim::needle
