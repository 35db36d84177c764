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

namespace {

// A lip's bound across a 3D bevel's seam through the axis (along bevelSide, from the axis plane), its axial
// slope -d(bound)/ds (the needle's axial reaction per unit lateral force: the gap's growth per unit advance of
// the tip) and whether it is the tip (frictionless tip contact) or the shaft's outline.
struct LipBound {
  double a = 0.0, slope = 0.0;
  bool tip = true;
};

// Wall-side lip: at or below the 2D virtual chisel across the chord ahead of the point, s tan(beta) - w, then the
// lower outline -w.
LipBound wallLipCeiling3D(double s, double w, double tb) {
  if (s > 0.0) return {s * tb - w, tb, true};
  return {-w, 0.0, false};
}

// Bevel-side lip: at or above
//  - ahead of the hold (s > w / tan(beta)) the wall-side chisel mirrored about the axis plane, w - s tan(beta):
//    below the plane, so it meets only a lip dragged down by its still-cohesive partner, and zero where the hold
//    begins, so the gap is continuous in s (a hold switched on at s = w / tan(beta) would give a lip already below
//    the plane the gap -a at once: work done by the contact that no energy term records);
//  - the hold on the axis plane until the bevel face -R - s tan(alpha) rises above it, the face, the upper outline w.
LipBound bevelLipFloor3D(double s, double w, double R, double ta, double tb) {
  if (s > w / tb) return {w - s * tb, tb, true};
  const double face = -R - s * ta;
  if (face <= 0.0) return {0.0, 0.0, true};
  if (face < w) return {face, ta, true};
  return {w, 0.0, false};
}

// Bevel-side lip of the slit through the sharp point: at or above the wall-side chisel mirrored about the slit's
// plane ahead of the point, -R - s tan(beta), then the bevel face continued across the chord, -R - s tan(alpha),
// up to the upper outline w.
LipBound bevelLipFloorPointSlit3D(double s, double w, double R, double ta, double tb) {
  if (s > 0.0) return {-R - s * tb, tb, true};
  const double face = -R - s * ta;
  if (face < w) return {face, ta, true};
  return {w, 0.0, false};
}

// The lip's hit from its bound (a along bevelSide from the axis) and slope; false where the lip is clear of it.
bool lipHit(const needle::NeedlePose& pose, const LipBound& bound, double a, int side, needle::NeedleHit& hit,
            double& axialPerLateral) {
  const double gap = side > 0 ? bound.a - a : a - bound.a;
  if (!(gap > 0.0)) return false;
  hit.inside = true;
  hit.depth = gap;
  hit.normal = (side > 0 ? 1.0 : -1.0) * pose.bevelSide;
  hit.face = bound.tip ? needle::NeedleFace::Tip : needle::NeedleFace::OuterWall;
  axialPerLateral = bound.slope;
  return true;
}

// The lip hit of a 3D slit whose bevel-side lip lies on `bevelFloor` (s, w, R, tan(tip), tan(ramp)); the
// wall-side lip below the lower outline in both slits.
bool slitWedge3D(const needle::NeedleShape& sh, const needle::NeedlePose& pose, const Eigen::Vector3d& x, int side,
                 LipBound (*bevelFloor)(double, double, double, double, double), needle::NeedleHit& hit,
                 double& axialPerLateral) {
  if (sh.tip != TipType::Bevel || side == 0) return false;
  const Eigen::Vector3d q = x - pose.tip, third = pose.axis.cross(pose.bevelSide);
  const double s = q.dot(pose.axis), a = q.dot(pose.bevelSide), b = q.dot(third), R = sh.radius;
  if (s < -sh.length || std::abs(b) >= R) return false;
  const double w = std::sqrt(R * R - b * b), ta = std::tan(sh.tipAngle), tb = std::tan(needle::kLipRampAngle);
  const LipBound bound = side > 0 ? bevelFloor(s, w, R, ta, tb) : wallLipCeiling3D(s, w, tb);
  return lipHit(pose, bound, a, side, hit, axialPerLateral);
}

}  // namespace

// The seam through the axis: from the lower outline (reached by the wall-side chisel ahead of the point) up to
// the axis plane, and above it the needle where it rises over the plane (the bevel face, then the upper outline).
bool bevelWedge3D(const needle::NeedleShape& sh, const needle::NeedlePose& pose, const Eigen::Vector3d& x, int side,
                  needle::NeedleHit& hit, double& axialPerLateral) {
  return slitWedge3D(sh, pose, x, side, bevelLipFloor3D, hit, axialPerLateral);
}

// The slit opened where the bevel cuts: the bevel-side lip lifted from the plane through the sharp point by the
// face to the upper outline; the wall-side lip below the lower outline, which it meets only if it rises.
bool bevelSlitWedge3D(const needle::NeedleShape& sh, const needle::NeedlePose& pose, const Eigen::Vector3d& x, int side,
                      needle::NeedleHit& hit, double& axialPerLateral) {
  return slitWedge3D(sh, pose, x, side, bevelLipFloorPointSlit3D, hit, axialPerLateral);
}

bool lipWedge(const needle::NeedleShape& sh, const needle::NeedlePose& pose, const Eigen::Vector3d& x, int side,
              LipSeam seam, needle::NeedleHit& hit, double& axialPerLateral) {
  if (seam == LipSeam::Planar) return bevelWedge2D(sh, pose, x, side, hit, axialPerLateral);
  if (sh.tip == TipType::Bevel)
    return seam == LipSeam::ThroughPoint ? bevelSlitWedge3D(sh, pose, x, side, hit, axialPerLateral)
                                         : bevelWedge3D(sh, pose, x, side, hit, axialPerLateral);
  return coneWedge(sh, pose, x, side, hit, axialPerLateral);
}

}  // namespace needlesim::explicit_fe
