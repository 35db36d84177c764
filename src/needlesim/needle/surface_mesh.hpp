#pragma once
// Rigid needle surfaces from the needle geometry, used by the explicit FE
// contact, MPM's surface contact (CFEMP) and MPM's needle output (MPM's grid
// contact takes the needle as its own analytic rigid body, mpm::RigidBody):
// solid or hollow cylinder with a bevel of any angle
// (seed 001 section 3.1: hollow 2.77/2.16 mm, 12 deg bevel; seed 004: 10-80 deg),
// a conical or a blunt (flat) tip.
//
// Needle frame: the tip (most distal point) at `tip`, unit axis `axis`
// pointing in the insertion direction, unit `bevelSide` perpendicular to it.
// The bevel plane passes through the tip point tip - ... (the sharp point lies
// on the wall at -R bevelSide from the axis) and makes the angle alpha with
// the axis, so the heel lies 2R/tan(alpha) behind the tip on the +bevelSide
// wall. Its outward normal is n = sin(alpha) axis + cos(alpha) bevelSide.
//
// Two views of the same solid: an exact inside/outside query (penetration
// depth, outward normal and face for penalty contact), and a triangulated
// surface (3D) or closed outlines (2D plane through the axis) for output and
// for engines that need explicit facets. Faces are tagged so that contact can
// be frictionless on the tip and frictional on the wall (seed 001 section 3.2).
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <vector>

#include "needlesim/needle/needle_spec.hpp"

namespace needlesim::needle {

enum class NeedleFace { OuterWall = 0, InnerWall = 1, Tip = 2, Base = 3 };

struct NeedleShape {
  double radius = 0.0;        // m, outer
  double innerRadius = 0.0;   // m, 0 = solid
  double length = 0.0;        // m, tip to base along the axis
  double tipAngle = 0.0;      // rad, angle between tip surface and axis (bevel alpha; cone half-angle)
  TipType tip = TipType::Bevel;

  static NeedleShape fromSpec(const NeedleSpec& spec);
};

struct NeedlePose {
  Eigen::Vector3d tip = Eigen::Vector3d::Zero();
  Eigen::Vector3d axis = Eigen::Vector3d::UnitX();
  Eigen::Vector3d bevelSide = Eigen::Vector3d::UnitY();
};

struct NeedleHit {
  bool inside = false;
  double depth = 0.0;              // m, distance to leave the needle through `face`
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();  // outward unit normal of that face
  NeedleFace face = NeedleFace::OuterWall;
};

// Inside test with penetration depth: the solid is the intersection of
// r < R, r > R_i, the tip half-space (or cone) and s > -L; the exit is through
// the constraint with the smallest margin. O(1) per point, no allocation.
// planar = true: a 2D plane-strain slice through the axis (r = |offset along bevelSide|).
// side: crack-lip hint for the two faces of a cut through the bevel's sharp point
// (a seam or cohesive zone). At the sharp point the nearest exit is ambiguous: a
// lip node a hair on the wrong side would be scooped onto the other lip's face and
// dragged along (it stopped 2D quad insertions on hourglassing near the entry).
// side < 0 (the lip on the wall side, -bevelSide): never leaves through the bevel;
// side > 0 (the bevel-side lip): never through the wall half facing -bevelSide (2D: that lip
// sees no lower wall but the bevel face continued across the cut line, one radius deep, so its
// depth stays continuous where it crosses the cut line behind the sharp point);
// 0: nearest exit. If no allowed exit exists the nearest one is used. A side < 0 node
// ahead of the sharp point meets a virtual chisel: the ramp a = -R + s tan(kLipRampAngle)
// from the sharp point (face Tip), so a lip lifted above the cut line is pushed under
// the wall gradually; the node-release seam's stand-in for the crack tip's wedge.
constexpr double kLipRampAngle = 0.5235987755982988;  // 30 deg
// 3D: the side hint holds only while an allowed exit lies within this fraction of the radius;
// beyond it the node has crossed the forbidden face and leaves through its nearest exit.
constexpr double kLipHintReach = 0.1;
NeedleHit queryNeedle(const NeedleShape& shape, const NeedlePose& pose, const Eigen::Vector3d& p,
                      bool planar, int side = 0);

struct SurfaceMesh {
  std::vector<double> points;     // 3 per point (2D outlines: z = 0)
  std::vector<int> cells;         // 3 per triangle (3D) or 2 per segment (2D)
  std::vector<NeedleFace> faces;  // per cell
  int pointsPerCell = 3;
};

// Closed triangulated surface, outward oriented. nCirc segments around, nAxial along the wall.
SurfaceMesh needleSurface3D(const NeedleShape& shape, const NeedlePose& pose, int nCirc = 32,
                            int nAxial = 8);
// Closed outline(s) of the plane section through the axis and bevelSide
// (two for a hollow needle), counter-clockwise seen from axis x bevelSide.
SurfaceMesh needleOutline2D(const NeedleShape& shape, const NeedlePose& pose);

}  // namespace needlesim::needle
