// The inclusions of a trainer frame (inclusion_readout.hpp).
#include "needlesim/live/inclusion_readout.hpp"

#include <Eigen/Core>

#include "needlesim/results/target_miss.hpp"

namespace needlesim::live {

namespace {

// The mean displacement of the region's vertices (0 for none, or a field without them).
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

std::vector<InclusionReadout> inclusionReadouts(const std::vector<api::Inclusion>& inclusions,
                                                const api::SurfaceField& field, const std::vector<double>& needle) {
  const std::size_t points = needle.size() / 3;
  const bool tipKnown = points >= 2;
  const Eigen::Vector3d tip = tipKnown ? point(needle, points - 1) : Eigen::Vector3d::Zero();
  const Eigen::Vector3d axis = tipKnown ? Eigen::Vector3d(tip - point(needle, points - 2)) : Eigen::Vector3d::UnitX();
  std::vector<InclusionReadout> out;
  out.reserve(inclusions.size());
  for (const api::Inclusion& I : inclusions) {
    const Eigen::Vector3d centre(I.x, I.y, I.z);
    const Eigen::Vector3d u = regionDisplacement(I.region, field.displacement);
    InclusionReadout r;
    r.centre = {centre.x() + u.x(), centre.y() + u.y(), centre.z() + u.z()};
    if (I.target && tipKnown && axis.norm() > 0.0) {
      const results::TargetMiss miss = results::targetMiss(centre, u, tip, axis);
      r.miss = miss.distance;
      r.missFromAxis = miss.fromAxis;
    }
    out.push_back(r);
  }
  return out;
}

}  // namespace needlesim::live
