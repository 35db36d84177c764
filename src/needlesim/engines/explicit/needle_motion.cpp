#include "needlesim/engines/explicit/needle_motion.hpp"

#include <cmath>

#include "needlesim/engines/explicit/path_needle.hpp"
#include "needlesim/engines/explicit/solver.hpp"

namespace needlesim::explicit_fe {

using Eigen::Vector3d;

Vector3d needleSurfaceVelocity(const RigidNeedle& n, const Vector3d& x) {
  Vector3d v = n.velocity * n.pose.axis;
  if (n.spinRate != 0.0) v += n.spinRate * n.pose.axis.cross(x - n.pose.tip);
  return v;
}

void advanceNeedle(RigidNeedle& n, double dt) {
  if (n.path) {  // follow-the-leader: the tip moves along its path (path_needle.hpp)
    placeOnPath(n, n.station + dt * n.velocity);
    return;
  }
  n.pose.tip += dt * n.velocity * n.pose.axis;
  if (n.spinRate != 0.0) {
    const Eigen::AngleAxisd rot(n.spinRate * dt, n.pose.axis);
    n.pose.bevelSide = (rot * n.pose.bevelSide).normalized();
  }
}

Vector3d bevelSideAt(double angle, const Vector3d& e1, const Vector3d& e2, int dim) {
  if (dim == 2) return (std::cos(angle) >= 0 ? 1.0 : -1.0) * e1;
  return std::cos(angle) * e1 + std::sin(angle) * e2;
}

}  // namespace needlesim::explicit_fe
