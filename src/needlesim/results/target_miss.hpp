#pragma once
// How far the needle misses a target inclusion (docs/results.md): from the needle tip to the
// target's displaced centre, and that centre's distance from the needle's axis. One definition
// for a run's key results (inclusion_motion.cpp) and the trainer's live readout (live/).
#include <Eigen/Core>

namespace needlesim::results {

struct TargetMiss {
  double distance = 0.0;  // m, tip to the displaced centre
  double fromAxis = 0.0;  // m, the displaced centre from the needle's axis (the line through the tip)
};

// centre: the target's reference centre; displacement: the mean displacement of its material;
// tip and axis (any length > 0): the needle's, all in the tissue frame.
TargetMiss targetMiss(const Eigen::Vector3d& centre, const Eigen::Vector3d& displacement, const Eigen::Vector3d& tip,
                      const Eigen::Vector3d& axis);

}  // namespace needlesim::results
