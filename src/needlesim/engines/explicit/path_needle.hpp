#pragma once
// Follow-the-leader rigid needle along a 2D path (docs/models/cohesive.md "Crack path").
// A flexible bevel-tip needle that is pushed along the channel its tip cuts occupies that
// channel behind the tip (follow-the-leader); every material point of the shaft moves with the
// insertion speed along the local tangent. The contact sees, at each tissue point x, the
// straight needle of needle/surface_mesh.hpp in the local frame of the path station nearest to
// x: axis = the path tangent there, bevelSide = the path normal (on the bevel's side), the tip
// placed one arc length (sigma_tip - sigma) ahead along that tangent. Points ahead of the tip
// use the tip's frame (the bevel oriented along the tip tangent). The path is the needle AXIS
// (the crack runs through the bevel's sharp point, offset by -R bevelSide); it is given before
// the run (user points, an arc, or the steering model's predicted tip path) and not changed by
// the run (one-way coupling).
#include <Eigen/Core>
#include <vector>

#include "needlesim/needle/surface_mesh.hpp"

namespace needlesim::explicit_fe {

struct RigidNeedle;
class CohesiveInterface;

class NeedlePath {
 public:
  // points: the axis path in the x-y plane, x strictly increasing, the needle entering at
  // points[0] (arc length 0). Extended straight along the end tangents by `before` behind the
  // first point and `after` beyond the last, then resampled uniformly in arc length with a
  // spacing <= ds. Throws Error for fewer than 2 points or x not increasing.
  NeedlePath(const std::vector<Eigen::Vector2d>& points, double before, double after, double ds);
  double begin() const { return s0_; }                                  // arc length of the first sample
  double end() const { return s0_ + (static_cast<double>(q_.size()) - 1) * hs_; }
  Eigen::Vector2d point(double sigma) const;
  Eigen::Vector2d tangent(double sigma) const;  // unit; vertex tangents interpolated along the segment
  Eigen::Vector2d normal(double sigma) const {  // tangent turned +90 deg
    const Eigen::Vector2d t = tangent(sigma);
    return {-t.y(), t.x()};
  }
  // Arc length of the point of the path nearest to x (walk from the sample at x's abscissa).
  double station(const Eigen::Vector2d& x) const;
  // The path offset by d along its normal, as a polyline (x increasing for |d| below the
  // radius of curvature), for the seam through the bevel's sharp point.
  std::vector<Eigen::Vector2d> offset(double d) const;
  // |y - path height at x| <= reach (O(1)): a cheap test before station() (the path turns at most
  // 45 deg from the x axis, so a point within distance d of it has |y - height| <= sqrt(2) d)
  bool near(const Eigen::Vector2d& x, double reach) const;

 private:
  std::vector<Eigen::Vector2d> q_, t_;  // samples and their (vertex) tangents
  double s0_ = 0.0, hs_ = 0.0;
  std::vector<int> cell_;  // uniform x cells -> the last sample at or before the cell's start
  double x0_ = 0.0, hx_ = 1.0;
  void locate(double sigma, int& k, double& u) const;
  int segmentAt(double x) const;  // the sample segment whose x range holds x (clamped)
};

// Local straight pose of the needle for the tissue point x (above).
needle::NeedlePose pathPose(const RigidNeedle& n, const Eigen::Vector3d& x);
// The same, false (pose untouched) when x lies beyond 4 radii across the path: no part of the
// needle reaches it (the solver's quick rejection).
bool pathPoseNear(const RigidNeedle& n, const Eigen::Vector3d& x, needle::NeedlePose& pose);
// Puts the needle's tip at arc length `station` of its path: pose.tip, axis, bevelSide.
void placeOnPath(RigidNeedle& n, double station);
// Where the lips of the seam pairs lie across the path (the tissue opened along it): for the pairs
// whose wall-side node a has its nearest station in [sMin, sMax], the signed offsets of a and b from
// the axis path along the local bevelSide (a: expected -R, b: +R once the shaft passed).
struct LipOffsets {
  int pairs = 0;
  double meanA = 0.0, meanB = 0.0;  // m
  double maxA = -1e300, minB = 1e300;  // the worst lips: a should stay < 0, b > 0
};
LipOffsets pathLipOffsets(const RigidNeedle& n, const CohesiveInterface& c, const std::vector<double>& X,
                          const std::vector<double>& u, double sMin, double sMax);
// 2D outline of the bent needle (solid section; the shaft sampled along the path) for output,
// `samples` points per wall; fixed topology for a given `samples`.
needle::SurfaceMesh pathNeedleOutline2D(const RigidNeedle& n, int samples = 40);

}  // namespace needlesim::explicit_fe
