// The inclusions as a viewer shows them (inclusion_view.hpp).
#include "needlesim/results/inclusion_view.hpp"

namespace needlesim::results {

namespace {

// The mean displacement of the region's nodes (0 for none, or a field without them).
Eigen::Vector3d regionDisplacement(const std::vector<int>& region, const std::vector<double>& displacement) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  std::size_t counted = 0;
  for (const int v : region) {
    const std::size_t at = 3 * static_cast<std::size_t>(v);
    if (v < 0 || at + 2 >= displacement.size()) continue;
    sum += Eigen::Vector3d(displacement[at], displacement[at + 1], displacement[at + 2]);
    ++counted;
  }
  return counted ? Eigen::Vector3d(sum / static_cast<double>(counted)) : Eigen::Vector3d::Zero();
}

Eigen::Vector3d point(const std::vector<double>& line, std::size_t index) {
  return {line[3 * index], line[3 * index + 1], line[3 * index + 2]};
}

}  // namespace

const char* inclusionShapeName(InclusionSpec::Shape shape) {
  switch (shape) {
    case InclusionSpec::Shape::Cylinder: return "cylinder";
    case InclusionSpec::Shape::Mesh: return "mesh";
    default: return "sphere";
  }
}

InclusionAtStep inclusionAtStep(const Eigen::Vector3d& centre, bool target, const std::vector<int>& region,
                                const std::vector<double>& displacement, const std::vector<double>& needle) {
  const Eigen::Vector3d u = regionDisplacement(region, displacement);
  InclusionAtStep out;
  out.centre = centre + u;
  const std::size_t points = needle.size() / 3;
  if (!target || points < 2) return out;
  const Eigen::Vector3d tip = point(needle, points - 1), axis = tip - point(needle, points - 2);
  if (axis.norm() > 0.0) out.miss = targetMiss(centre, u, tip, axis);
  return out;
}

}  // namespace needlesim::results
