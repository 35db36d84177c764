#include "needlesim/needle/surface_mesh.hpp"

#include <Eigen/Geometry>
#include <cmath>
#include <limits>

#include "needlesim/core/error.hpp"

namespace needlesim::needle {

using Eigen::Vector3d;

NeedleShape NeedleShape::fromSpec(const NeedleSpec& s) {
  NeedleShape n;
  n.radius = 0.5 * s.outer_diameter;
  n.innerRadius = 0.5 * s.inner_diameter;
  n.length = s.length;
  n.tip = s.tip;
  n.tipAngle = s.tip == TipType::Blunt ? 0.5 * M_PI : s.bevel_angle;
  if (!(n.radius > 0) || !(n.length > 0) || n.innerRadius < 0 || n.innerRadius >= n.radius)
    throw Error("needle geometry: need outer diameter > inner diameter >= 0 and length > 0");
  if (!(n.tipAngle > 0 && n.tipAngle <= 0.5 * M_PI + 1e-12))
    throw Error("needle geometry: tip angle must lie in (0, 90] deg");
  return n;
}

namespace {
struct Local {
  double s, a, b, r;  // axial (0 at tip, < 0 along the body), along bevelSide, along third, radius
  Vector3d rhat;      // radial unit vector (bevelSide when on the axis)
};
Local toLocal(const NeedlePose& pose, const Vector3d& p, bool planar) {
  Vector3d q = p - pose.tip;
  Local l;
  l.s = q.dot(pose.axis);
  l.a = q.dot(pose.bevelSide);
  Vector3d third = pose.axis.cross(pose.bevelSide);
  l.b = planar ? 0.0 : q.dot(third);
  l.r = std::hypot(l.a, l.b);
  l.rhat = l.r > 1e-300 ? Vector3d((l.a * pose.bevelSide + l.b * third) / l.r) : pose.bevelSide;
  return l;
}
// 2D (plane through the axis), bevel-side lip: the lower wall is its forbidden exit (header), so the
// needle this lip sees has no lower wall; its bevel face continues across the cut line. With the lower
// wall as a boundary the depth would jump from 0 (a hair below the cut line, outside) to the bevel
// margin, ~ sin(alpha) x the distance behind the sharp point (a hair above it, inside): penalty energy
// U = k d^2 / 2 (contact/penalty.hpp) out of nothing at every crossing (seed 004 Fig 13, 80 deg bevel:
// the entry corner node crosses back and forth; needle energy balance 77 % that way). On the continued face the
// depth is the bevel plane's margin m = -(s sin(alpha) + (a + R) cos(alpha)) (the plane of the header)
// wherever the lip is, so the force k m n is -dU/dx and does no work over a closed path; the face stands
// in for the wall-side lip's material under the bevel-side lip at the point, as the chisel does for
// the wall-side lip.
bool bevelFaceContinued(const NeedleShape& sh, bool planar, int side) {
  return planar && side > 0 && sh.tip == TipType::Bevel;
}

// The region of the continued face: across the needle's width plus one radius below the cut line
// (a lip node further below would have broken the penetration tolerance long before).
bool withinContinuedFace(double a, double R) { return a <= R && a >= -2.0 * R; }
}  // namespace

NeedleHit queryNeedle(const NeedleShape& sh, const NeedlePose& pose, const Vector3d& p, bool planar, int side) {
  NeedleHit h;
  const Local l = toLocal(pose, p, planar);
  const double R = sh.radius;
  // Wall-side lip ahead of the sharp point: a virtual chisel, the ramp a = -R + s tan(beta)
  // rising from the sharp point (beta = kLipRampAngle), pushes a lip node lifted above the
  // cut line down gradually as the tip approaches instead of by a jump when the tip passes.
  if (side < 0 && sh.tip == TipType::Bevel && l.s > 0.0) {
    const double tb = std::tan(kLipRampAngle), g = l.a + R - l.s * tb;
    if (l.r >= R || g <= 0.0) return h;
    h.inside = true;
    h.depth = g * std::cos(kLipRampAngle);
    h.normal = std::sin(kLipRampAngle) * pose.axis - std::cos(kLipRampAngle) * pose.bevelSide;
    h.face = NeedleFace::Tip;
    return h;
  }
  // Quick rejection: outside the bounding cylinder (for a 2D bevel-side lip: the needle with its bevel
  // face continued below the cut line, see bevelFaceContinued).
  if (bevelFaceContinued(sh, planar, side) ? !withinContinuedFace(l.a, R) : l.s > 0.0 || l.r > R) return h;
  if (l.s < -sh.length) return h;
  // Crack-lip hint (see the header): a lip never leaves through the other lip's side of the sharp point.
  const bool lowerWall = l.rhat.dot(pose.bevelSide) < 0.0;
  const bool wallAllowed = !(side > 0 && lowerWall);
  const bool tipAllowed = !(side < 0 && sh.tip == TipType::Bevel);
  double best = wallAllowed ? R - l.r : std::numeric_limits<double>::infinity();
  Vector3d n = l.rhat;
  NeedleFace face = NeedleFace::OuterWall;
  auto consider = [&](double margin, const Vector3d& normal, NeedleFace f) {
    if (f == NeedleFace::Tip && !tipAllowed) return;
    if (margin < best) {
      best = margin;
      n = normal;
      face = f;
    }
  };
  if (sh.innerRadius > 0.0) {
    if (l.r < sh.innerRadius) return h;
    consider(l.r - sh.innerRadius, -l.rhat, NeedleFace::InnerWall);
  }
  const double ca = std::cos(sh.tipAngle), sa = std::sin(sh.tipAngle);
  if (sh.tip == TipType::Conical) {
    // cone r <= (-s) tan(alpha) with apex at the tip
    double m = (-l.s * sa / ca - l.r) * ca;
    if (m <= 0.0) return h;
    consider(m, Vector3d(sa * pose.axis + ca * l.rhat), NeedleFace::Tip);
  } else {
    // bevel plane through the sharp point (s = 0, a = -R), normal n = sin a axis + cos a bevelSide
    double m = -(sa * l.s + ca * (l.a + R));
    if (m <= 0.0) return h;
    consider(m, Vector3d(sa * pose.axis + ca * pose.bevelSide), NeedleFace::Tip);
  }
  consider(l.s + sh.length, -pose.axis, NeedleFace::Base);
  if (!std::isfinite(best)) return queryNeedle(sh, pose, p, planar, 0);  // no allowed exit: nearest one
  // In 3D the hint settles a hair's ambiguity at the sharp point only. Off the axis plane the seam
  // plane and the round wall part: a bevel-side lip node in the sliver between them lies under the
  // needle and meets its lower wall from outside. A lip node whose allowed exits all lie deeper than
  // a tenth of the radius crossed the forbidden face (a node moves far less in a step); pushing it
  // out through the other side would be a jump of that depth, so it takes its nearest exit.
  // (Imported gland, examples/anatomy: needle energy balance 645 -> 4e-4 over 3.3 mm.) In 2D the
  // seam line is the wall's line: no sliver, and the hint holds everywhere.
  if (!planar && side != 0 && best > kLipHintReach * R) return queryNeedle(sh, pose, p, planar, 0);
  if (!(best > 0.0)) return h;
  h.inside = true;
  h.depth = best;
  h.normal = n;
  h.face = face;
  return h;
}

namespace {
// Axial coordinate where the wall of radius rho at angle theta (a = rho cos theta) meets the tip surface.
double wallEnd(const NeedleShape& sh, double rho, double theta) {
  if (sh.tip == TipType::Conical) return -rho / std::tan(sh.tipAngle);
  const double t = std::tan(sh.tipAngle);
  return std::isfinite(t) && t < 1e12 ? -(sh.radius + rho * std::cos(theta)) / t : 0.0;
}
}  // namespace

SurfaceMesh needleSurface3D(const NeedleShape& sh, const NeedlePose& pose, int nCirc, int nAxial) {
  SurfaceMesh m;
  m.pointsPerCell = 3;
  const Vector3d e = pose.bevelSide, f = pose.axis.cross(pose.bevelSide);
  auto point = [&](double s, double rho, double th) {
    Vector3d p = pose.tip + s * pose.axis + rho * (std::cos(th) * e + std::sin(th) * f);
    m.points.insert(m.points.end(), {p.x(), p.y(), p.z()});
    return static_cast<int>(m.points.size() / 3 - 1);
  };
  auto P = [&](int i) { return Vector3d(m.points[3 * i], m.points[3 * i + 1], m.points[3 * i + 2]); };
  auto tri = [&](int a, int b, int c, NeedleFace face, const Vector3d& expectedNormal) {
    Vector3d nrm = (P(b) - P(a)).cross(P(c) - P(a));
    if (nrm.dot(expectedNormal) < 0) std::swap(b, c);
    m.cells.insert(m.cells.end(), {a, b, c});
    m.faces.push_back(face);
  };
  const double ca = std::cos(sh.tipAngle), sa = std::sin(sh.tipAngle);
  const Vector3d bevelN = sa * pose.axis + ca * e;
  // Walls: outer (outward radial) and inner (inward radial).
  std::vector<int> outerEnd(nCirc), innerEnd(nCirc), outerBase(nCirc), innerBase(nCirc);
  for (int w = 0; w < (sh.innerRadius > 0 ? 2 : 1); ++w) {
    const double rho = w == 0 ? sh.radius : sh.innerRadius;
    std::vector<int> grid((nAxial + 1) * nCirc);
    for (int k = 0; k < nCirc; ++k) {
      double th = 2 * M_PI * k / nCirc;
      double s1 = wallEnd(sh, rho, th);
      for (int j = 0; j <= nAxial; ++j) grid[j * nCirc + k] = point(-sh.length + (s1 + sh.length) * j / nAxial, rho, th);
      (w == 0 ? outerEnd : innerEnd)[k] = grid[nAxial * nCirc + k];
      (w == 0 ? outerBase : innerBase)[k] = grid[k];
    }
    for (int j = 0; j < nAxial; ++j)
      for (int k = 0; k < nCirc; ++k) {
        int k1 = (k + 1) % nCirc;
        int a = grid[j * nCirc + k], b = grid[j * nCirc + k1], c = grid[(j + 1) * nCirc + k1],
            d = grid[(j + 1) * nCirc + k];
        double th = 2 * M_PI * (k + 0.5) / nCirc;
        Vector3d rad = std::cos(th) * e + std::sin(th) * f;
        if (w == 1) rad = -rad;
        NeedleFace face = w == 0 ? NeedleFace::OuterWall : NeedleFace::InnerWall;
        tri(a, b, c, face, rad);
        tri(a, c, d, face, rad);
      }
  }
  // Tip face and base: annulus between outer and inner rings, or a fan from the centre.
  auto cap = [&](const std::vector<int>& outer, const std::vector<int>& inner, int centre, NeedleFace face,
                 bool cone) {
    for (int k = 0; k < nCirc; ++k) {
      int k1 = (k + 1) % nCirc;
      Vector3d nrm;
      if (face == NeedleFace::Base) nrm = -pose.axis;
      else if (cone) {
        double th = 2 * M_PI * (k + 0.5) / nCirc;
        nrm = sa * pose.axis + ca * (std::cos(th) * e + std::sin(th) * f);
      } else nrm = bevelN;
      if (sh.innerRadius > 0) {
        tri(outer[k], outer[k1], inner[k1], face, nrm);
        tri(outer[k], inner[k1], inner[k], face, nrm);
      } else {
        tri(outer[k], outer[k1], centre, face, nrm);
      }
    }
  };
  int tipCentre = -1, baseCentre = -1;
  if (sh.innerRadius <= 0) {
    tipCentre = sh.tip == TipType::Conical ? point(0.0, 0.0, 0.0) : point(wallEnd(sh, 0.0, 0.0), 0.0, 0.0);
    baseCentre = point(-sh.length, 0.0, 0.0);
  }
  cap(outerEnd, innerEnd, tipCentre, NeedleFace::Tip, sh.tip == TipType::Conical);
  cap(outerBase, innerBase, baseCentre, NeedleFace::Base, false);
  return m;
}

SurfaceMesh needleOutline2D(const NeedleShape& sh, const NeedlePose& pose) {
  SurfaceMesh m;
  m.pointsPerCell = 2;
  const double R = sh.radius, Ri = sh.innerRadius, L = sh.length;
  auto add = [&](double s, double a) {
    Vector3d p = pose.tip + s * pose.axis + a * pose.bevelSide;
    m.points.insert(m.points.end(), {p.x(), p.y(), p.z()});
    return static_cast<int>(m.points.size() / 3 - 1);
  };
  auto loop = [&](const std::vector<std::pair<int, NeedleFace>>& pts) {
    for (std::size_t i = 0; i < pts.size(); ++i) {
      m.cells.insert(m.cells.end(), {pts[i].first, pts[(i + 1) % pts.size()].first});
      m.faces.push_back(pts[i].second);
    }
  };
  // Each vertex carries the face of the edge that leaves it.
  auto sEnd = [&](double a) {  // tip surface at lateral offset a
    if (sh.tip == TipType::Conical) return -std::abs(a) / std::tan(sh.tipAngle);
    double t = std::tan(sh.tipAngle);
    return t < 1e12 ? -(R + a) / t : 0.0;
  };
  using F = NeedleFace;
  if (Ri <= 0) {
    if (sh.tip == TipType::Conical)
      loop({{add(-L, -R), F::OuterWall}, {add(sEnd(-R), -R), F::Tip}, {add(0, 0), F::Tip},
            {add(sEnd(R), R), F::OuterWall}, {add(-L, R), F::Base}});
    else
      loop({{add(-L, -R), F::OuterWall}, {add(sEnd(-R), -R), F::Tip}, {add(sEnd(R), R), F::OuterWall},
            {add(-L, R), F::Base}});
  } else {
    loop({{add(-L, -R), F::OuterWall}, {add(sEnd(-R), -R), F::Tip}, {add(sEnd(-Ri), -Ri), F::InnerWall},
          {add(-L, -Ri), F::Base}});
    loop({{add(-L, Ri), F::InnerWall}, {add(sEnd(Ri), Ri), F::Tip}, {add(sEnd(R), R), F::OuterWall},
          {add(-L, R), F::Base}});
  }
  return m;
}

}  // namespace needlesim::needle
