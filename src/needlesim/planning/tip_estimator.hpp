#pragma once
// The closed loop's estimate of the needle's state from noisy tip measurements: a maximum a
// posteriori fit (Gauss-Newton) of the entry pose error (3 translations, 3 rotations) and the
// curvature's scale to every tip position measured so far, the kinematic model replaying the
// arcs executed (retractions along the channel included); the prior is the scenario's stated spread of each.
#include <array>
#include <vector>

#include "needlesim/planning/channel.hpp"

namespace needlesim::planning {

class TipEstimator {
 public:
  // nominal: the planned entry pose; sd: prior standard deviations of (x, y, z translation [m],
  // three rotations [rad], log curvature scale); noise: of one measurement, per axis [m].
  TipEstimator(const Pose& nominal, const std::array<double, 7>& sd, double noise);
  void executed(const Arc& arc) { arcs_.push_back(arc); }
  // A measured tip position after the arcs executed so far; the estimate is updated.
  void measured(const Vec3& tip);
  // The estimated tip pose now, and the estimated curvature scale.
  Pose pose() const { return replay(theta_, nullptr).tip(); }
  // The estimated tip pose were it pulled back to `depth` along its channel.
  Pose poseAt(double depth) const { return replay(theta_, nullptr).at(depth); }
  double depth() const { return replay(theta_, nullptr).depth(); }
  double curvatureScale() const;

 private:
  using Params = std::array<double, 7>;
  Pose nominal_;
  Params sd_;
  double noise_;
  Params theta_{};
  std::vector<Arc> arcs_;
  std::vector<std::size_t> at_;  // arcs executed before each measurement
  std::vector<Vec3> tips_;
  Channel replay(const Params& th, std::vector<Vec3>* predicted) const;
  std::vector<double> residuals(const Params& th) const;
};

}  // namespace needlesim::planning
