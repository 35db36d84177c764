// The needle's miss of a target (target_miss.hpp).
#include "needlesim/results/target_miss.hpp"

namespace needlesim::results {

TargetMiss targetMiss(const Eigen::Vector3d& centre, const Eigen::Vector3d& displacement, const Eigen::Vector3d& tip,
                      const Eigen::Vector3d& axis) {
  const Eigen::Vector3d d = centre + displacement - tip;
  const Eigen::Vector3d a = axis.normalized();
  return {d.norm(), (d - d.dot(a) * a).norm()};
}

}  // namespace needlesim::results
