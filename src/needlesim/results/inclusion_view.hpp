#pragma once
// The inclusions as a viewer shows them, one definition for the C++ API (api::Session::inclusions),
// the trainer's live readout (live/inclusion_readout) and Python's Session.inclusions: the
// shape's name, and at a step where the inclusion's material has moved (its reference centre
// plus the mean displacement of its region's nodes, as inclusions.csv) and, for a target, how far
// the needle misses it (target_miss.hpp), from the end of the needle's centre line.
#include <Eigen/Core>
#include <optional>
#include <vector>

#include "needlesim/results/target_miss.hpp"
#include "needlesim/scenario/scenario.hpp"

namespace needlesim::results {

// sphere, cylinder or mesh (a group of tissue.geometry).
const char* inclusionShapeName(InclusionSpec::Shape shape);

struct InclusionAtStep {
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();  // m, the displaced centre, tissue frame
  std::optional<TargetMiss> miss;                    // targets only, when the needle is known
};

// centre: the reference centre; region: node indices into `displacement` (x y z per node; those
// beyond it are skipped, none: no displacement); needle: x y z per point, base to tip (fewer
// than 2 points: no miss).
InclusionAtStep inclusionAtStep(const Eigen::Vector3d& centre, bool target, const std::vector<int>& region,
                                const std::vector<double>& displacement, const std::vector<double>& needle);

}  // namespace needlesim::results
