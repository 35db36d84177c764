#pragma once
// A rigid body of the MPM solver with prescribed translation (a plane or the
// needle) and its signed distance with analytic normals (seed 000 eq 22).
#include <Eigen/Core>

namespace needlesim::mpm {

using Vec3 = Eigen::Vector3d;

// A rigid body with prescribed translation: an infinite plane or a needle
// (cylinder with a conical or bevelled tip). Normals are analytic.
struct RigidBody {
  enum class Kind { Plane, Needle } kind = Kind::Plane;
  enum class Tip { Conical, Bevel, Blunt } tip = Tip::Conical;
  Vec3 point = Vec3::Zero();    // plane: a point on it; needle: the tip point
  Vec3 normal = Vec3::UnitZ();  // plane: outward normal (out of the rigid half-space)
  Vec3 axis = Vec3::UnitX();    // needle: unit insertion direction (base -> tip)
  // needle, bevel tip: the side the bevel face looks to (needle::NeedleShape's
  // bevelSide): the heel on +bevelSide, the sharp point at -radius bevelSide.
  Vec3 bevelSide = Vec3::UnitY();
  double radius = 0.0;          // needle radius, m
  double tipAngle = 0.35;       // rad: cone half-angle / bevel angle to the axis
  Vec3 velocity = Vec3::Zero(); // m/s
  double friction = 0.0;        // Coulomb coefficient against the tissue (eq 20)
  double tipFriction = 0.0;     // CFEMP: on the tip's surface
  bool surfaceContact = false;  // needle: CFEMP particle-to-surface contact (eqs 22-24) instead of grid contact
  double length = 0.04;         // needle: length tip to base, m (CFEMP surface)
  double elementSize = 0.0;     // CFEMP: d_e of the gap rule g < (d_e + d_p)/2 (eq 22), m
  // needle: the tissue parts along the needle's cut (needle_cut.cpp): no point
  // reaches a node across the strip of the plane through the axis normal to
  // bevelSide, as wide as the needle, that it has passed: the lips move apart.
  bool parting = false;
  // parting: the cut runs along the lower half of the needle's surface behind the bevel's face
  // (the path of its cutting edges) instead of the strip through the axis.
  bool cutAlongEdges = false;
  double cutAhead = 0.0;        // parting: the cut reaches this far ahead of the tip plane (a pre-cut path), m
  // Signed distance (negative inside), the outward unit normal at the nearest
  // face, and which part is nearest (0 shaft or plane, 1 tip).
  double distance(const Vec3& x, Vec3* n, int* part) const;
  // Needle: the axis point level with the tip (`point`, or R off a bevel's sharp point).
  Vec3 axisPoint() const { return tip == Tip::Bevel ? Vec3(point + radius * bevelSide) : point; }
};

}  // namespace needlesim::mpm
