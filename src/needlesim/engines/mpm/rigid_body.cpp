// Signed distance of a rigid body of the MPM solver (rigid_body.hpp): a plane,
// or the needle as the intersection of its shaft cylinder and its tip (cone,
// bevel face or blunt end). The GPU kernels hold the same function
// (cuda/mpm_device_kernels.hpp).
#include "needlesim/engines/mpm/rigid_body.hpp"

#include <cmath>

namespace needlesim::mpm {

double RigidBody::distance(const Vec3& x, Vec3* n, int* part) const {
  if (kind == Kind::Plane) {
    if (n) *n = normal;
    if (part) *part = 0;
    return (x - point).dot(normal);
  }
  const Vec3& e = axis;
  const Vec3 c = axisPoint();
  const Vec3 rel = x - c;
  const double s = -rel.dot(e);  // distance behind the tip plane along the axis
  Vec3 rv = rel + s * e;         // radial vector
  double r = rv.norm();
  Vec3 er = r > 1e-14 ? Vec3(rv / r) : bevelSide;
  const double dCyl = r - radius;
  double dTip;
  Vec3 nTip;
  switch (tip) {
    case Tip::Conical: {
      const double cb = std::cos(tipAngle), sb = std::sin(tipAngle);
      if (s * cb + r * sb <= 0.0) {  // nearest point is the apex
        dTip = rel.norm();
        nTip = dTip > 1e-14 ? Vec3(rel / dTip) : e;
      } else {
        dTip = r * cb - s * sb;
        nTip = cb * er + sb * e;
      }
      break;
    }
    case Tip::Bevel: {
      nTip = std::sin(tipAngle) * e + std::cos(tipAngle) * bevelSide;  // face of the bevel
      dTip = (x - point).dot(nTip);
      break;
    }
    case Tip::Blunt:
    default:
      nTip = e;
      dTip = -s;
      break;
  }
  if (dTip >= dCyl) {
    if (n) *n = nTip;
    if (part) *part = 1;
    return dTip;
  }
  if (n) *n = er;
  if (part) *part = 0;
  return dCyl;
}

}  // namespace needlesim::mpm
