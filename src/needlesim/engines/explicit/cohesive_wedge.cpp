#include "needlesim/engines/explicit/cohesive_wedge.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

namespace needlesim::explicit_fe {

bool coneWedge(const needle::NeedleShape& sh, const needle::NeedlePose& pose, const Eigen::Vector3d& x, int side,
               needle::NeedleHit& hit, double& axialPerLateral) {
  if (sh.tip != TipType::Conical || side == 0) return false;
  const Eigen::Vector3d q = x - pose.tip, third = pose.axis.cross(pose.bevelSide);
  const double s = q.dot(pose.axis), a = q.dot(pose.bevelSide), b = q.dot(third);
  if (s > 0.0 || s < -sh.length) return false;
  // radius of the solid at s: the cone r = -s tan(alpha) up to the shaft radius R
  const double t = std::tan(sh.tipAngle), rho = std::min(sh.radius, -s * t);
  if (std::abs(b) >= rho) return false;
  const double c = std::sqrt(rho * rho - b * b);  // lateral half-extent of the section at |b|
  const double gap = c - side * a;                // lateral distance to the surface on the own side
  if (!(gap > 0.0) || std::abs(a) >= c) return false;  // outside the section
  hit.inside = true;
  hit.depth = gap;
  hit.normal = side * pose.bevelSide;
  const bool onCone = -s * t < sh.radius;
  hit.face = onCone ? needle::NeedleFace::Tip : needle::NeedleFace::OuterWall;
  // d(gap)/d(advance) = rho tan(alpha) / c on the cone (0 on the shaft): the reaction f rho tan(alpha) / c stays
  // finite at grazing (|b| -> rho) since f = k gap and gap -> 0 with c
  axialPerLateral = onCone ? rho * t / std::max(c, 1e-9 * rho) : 0.0;
  return true;
}

bool bevelWedge2D(const needle::NeedleShape& sh, const needle::NeedlePose& pose, const Eigen::Vector3d& x, int side,
                  needle::NeedleHit& hit, double& axialPerLateral) {
  if (sh.tip != TipType::Bevel || side == 0) return false;
  const Eigen::Vector3d q = x - pose.tip;
  const double s = q.dot(pose.axis), a = q.dot(pose.bevelSide), R = sh.radius, ta = std::tan(sh.tipAngle);
  if (s < -sh.length || a >= R) return false;
  double gap = 0.0, slope = 0.0;
  needle::NeedleFace face = needle::NeedleFace::Tip;
  if (side > 0) {
    if (s > 0.0) return false;
    if (s >= -2.0 * R / ta) {
      gap = -(s * ta + a + R);  // under the bevel face
      slope = ta;
    } else {
      gap = R - a;  // behind the heel: the bevel-side wall (continuous with the face at the heel)
      face = needle::NeedleFace::OuterWall;
    }
  } else if (s > 0.0) {
    const double tb = std::tan(needle::kLipRampAngle);
    gap = a + R - s * tb;
    slope = tb;
  } else {
    gap = a + R;
    face = needle::NeedleFace::OuterWall;
  }
  if (!(gap > 0.0)) return false;
  hit.inside = true;
  hit.depth = gap;
  hit.normal = (side > 0 ? 1.0 : -1.0) * pose.bevelSide;
  hit.face = face;
  axialPerLateral = slope;
  return true;
}

bool bevelWedge3D(const needle::NeedleShape& sh, const needle::NeedlePose& pose, const Eigen::Vector3d& x, int side,
                  needle::NeedleHit& hit, double& axialPerLateral) {
  if (sh.tip != TipType::Bevel || side == 0) return false;
  const Eigen::Vector3d q = x - pose.tip, third = pose.axis.cross(pose.bevelSide);
  const double s = q.dot(pose.axis), a = q.dot(pose.bevelSide), b = q.dot(third), R = sh.radius;
  const double ta = std::tan(sh.tipAngle);
  if (s < -sh.length || std::abs(b) >= R) return false;
  const double w = std::sqrt(R * R - b * b);
  // the opened slit: from the lower outline (reached by the wall-side chisel ahead of the point) up to the
  // axis plane, and above it the needle where it rises over the plane (the bevel face, then the upper outline)
  double gap = 0.0, slope = 0.0;
  const double dir = side > 0 ? 1.0 : -1.0;
  needle::NeedleFace face = needle::NeedleFace::Tip;
  if (side > 0) {
    if (s > w / std::tan(needle::kLipRampAngle)) return false;
    const double faceA = -R - s * ta, top = std::max(0.0, std::min(w, faceA));
    gap = top - a;
    if (top > 0.0 && faceA < w) slope = ta;
    if (faceA >= w) face = needle::NeedleFace::OuterWall;
  } else {
    const double tb = std::tan(needle::kLipRampAngle);
    gap = a + w - std::max(0.0, s) * tb;  // the chisel ahead of the point, then the lower outline
    if (s > 0.0)
      slope = tb;
    else
      face = needle::NeedleFace::OuterWall;
  }
  if (!(gap > 0.0)) return false;
  hit.inside = true;
  hit.depth = gap;
  hit.normal = dir * pose.bevelSide;
  hit.face = face;
  axialPerLateral = slope;
  return true;
}

bool lipWedge(const needle::NeedleShape& sh, const needle::NeedlePose& pose, const Eigen::Vector3d& x, int side,
              bool planar, needle::NeedleHit& hit, double& axialPerLateral) {
  if (planar) return bevelWedge2D(sh, pose, x, side, hit, axialPerLateral);
  if (sh.tip == TipType::Bevel) return bevelWedge3D(sh, pose, x, side, hit, axialPerLateral);
  return coneWedge(sh, pose, x, side, hit, axialPerLateral);
}

}  // namespace needlesim::explicit_fe
