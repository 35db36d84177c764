#include "needlesim/engines/explicit/cohesive_sleeve.hpp"

#include <algorithm>
#include <cmath>

namespace needlesim::explicit_fe {

double sleeveEdge(const needle::NeedleShape& sh, double r, double cosTheta) {
  return -(r * cosTheta + sh.radius) / std::tan(sh.tipAngle);
}

bool sleeveWedge(const needle::NeedleShape& sh, const needle::NeedlePose& pose, const Eigen::Vector3d& x, int side,
                 double rs, needle::NeedleHit& hit, double& axialPerLateral, const Eigen::Vector3d* xRef) {
  if (sh.tip != TipType::Bevel || !(sh.innerRadius > 0) || side == 0) return false;
  const Eigen::Vector3d q = x - pose.tip;
  const double s = q.dot(pose.axis);
  if (s < -sh.length) return false;
  const Eigen::Vector3d lat = q - s * pose.axis;
  const double r = lat.norm();
  if (!(r > 1e-12 * sh.radius)) return false;
  const Eigen::Vector3d er = lat / r;
  // how far the edge has passed; the ramp extends ahead of the edge (delta < 0) as the 2D rule's chisel, so a
  // pair dragged off the sleeve as a whole meets it gradually instead of with a jump in depth at delta = 0
  // the edge's station from the reference azimuth when given: the gap then depends on the current position only
  // through r, so the radial push is its full gradient (a potential; the current azimuth made it non-conservative)
  double c = er.dot(pose.bevelSide);
  if (xRef) {
    const Eigen::Vector3d qr = *xRef - pose.tip, lr = qr - qr.dot(pose.axis) * pose.axis;
    if (lr.norm() > 1e-12 * sh.radius) c = lr.normalized().dot(pose.bevelSide);
  }
  const double delta = sleeveEdge(sh, rs, c) - s;
  const double tb = std::tan(needle::kLipRampAngle);
  double gap, target;
  bool ramp;
  if (side < 0) {
    target = std::max(sh.innerRadius, rs - delta * tb);
    ramp = target > sh.innerRadius;
    gap = r - target;
  } else {
    target = std::min(sh.radius, rs + delta * tb);
    ramp = target < sh.radius;
    gap = target - r;
  }
  if (!(gap > 0.0)) return false;
  hit.inside = true;
  hit.depth = gap;
  hit.normal = side < 0 ? Eigen::Vector3d(-er) : er;
  hit.face = ramp ? needle::NeedleFace::Tip : side < 0 ? needle::NeedleFace::InnerWall : needle::NeedleFace::OuterWall;
  axialPerLateral = ramp ? tb : 0.0;
  return true;
}

}  // namespace needlesim::explicit_fe
