#pragma once
// The needle wedging a still-cohesive seam open in 3D (docs/models/cohesive.md
// "The point wedges the seam open"): for a conical tip and a seam plane through
// the needle axis, a lip node inside the needle is pushed along its own side of
// the seam normal (side x bevelSide) to the needle surface, instead of along the
// surface normal (whose axial part would shove the closed pair ahead of the
// apex). The 2D bevel rule lives in solver.cpp; this is its 3D cone analogue.
// The same lip rules hold the lips of explicit 3D's node-release slit, the
// G_c -> 0 limit of the cohesive zone (seed 001 section 3.3, seed 004 eq 14).
#include <Eigen/Core>

#include "needlesim/needle/surface_mesh.hpp"

namespace needlesim::explicit_fe {

// x: current position of the lip node, side: +1 the lip on +bevelSide, -1 the other.
// On return, if the node is inside the cone or shaft: hit.inside, hit.depth (lateral
// distance to the surface along side x bevelSide), hit.normal = side x bevelSide,
// hit.face, and axialPerLateral = the axial force the needle feels per unit lateral
// force (d(lateral gap)/d(tip advance), so the needle's work equals the opening work).
// Returns false (hit untouched) for other tips or a node outside the needle.
bool coneWedge(const needle::NeedleShape& shape, const needle::NeedlePose& pose, const Eigen::Vector3d& x, int side,
               needle::NeedleHit& hit, double& axialPerLateral);

// 2D bevel (planar, seam through the sharp point): the same lateral wedge as one potential per
// lip, without the cylinder test (a lip dragged across the cut line by its still-cohesive partner
// must still meet the face, instead of entering later with a large depth):
//  side > 0 (bevel lip), under the bevel (-2R/tan(alpha) < s <= 0): gap = -(s tan(alpha) + a + R),
//    pushed along +bevelSide, needle reaction tan(alpha) per unit lateral force;
//  side < 0 (wall lip), ahead of the point (s > 0): the virtual chisel, gap = a + R - s tan(beta),
//    pushed along -bevelSide, reaction tan(beta); behind it (s <= 0, inside the shaft): gap = a + R.
// s, a: the node's axial and lateral coordinates from the tip (a from the axis along bevelSide).
bool bevelWedge2D(const needle::NeedleShape& shape, const needle::NeedlePose& pose, const Eigen::Vector3d& x, int side,
                  needle::NeedleHit& hit, double& axialPerLateral);

// 3D bevel, seam plane through the needle axis (normal bevelSide; the sharp point lies on the wall
// side, a = -R). With b the node's coordinate along the seam across the axis, w = sqrt(R^2 - b^2)
// the half chord of the outer section (|b| < R; a hollow needle is taken by its outer section):
//  side < 0 (wall lip): ahead of the point the virtual chisel of 2D across the whole chord,
//    gap = a + w - s tan(beta), reaction tan(beta); behind it gap = a + w (the lower outline);
//  side > 0 (bevel lip), gap = top - a: where the chisel reaches (s <= w / tan(beta)) held on the axis
//    plane, then lifted to top = max(0, min(w, -R - s tan(alpha))) (reaction tan(alpha) on the face);
//    ahead of that the chisel mirrored about the plane, top = w - s tan(beta) (reaction tan(beta)).
// Both gaps are continuous in s, so the lips end at +-w around the shaft, the eye-shaped opening of
// the cone wedge (docs/models/cohesive.md "3D bevel"). x: the node's position with its displacements
// along the axis and along the seam removed (solver.cpp), so the gap changes with the current
// position only across the seam and the lateral push is its gradient.
bool bevelWedge3D(const needle::NeedleShape& shape, const needle::NeedlePose& pose, const Eigen::Vector3d& x, int side,
                  needle::NeedleHit& hit, double& axialPerLateral);

// 3D bevel, node-release slit through the sharp point (the plane a = -R normal to bevelSide, |b| < R: the cut
// where the bevel makes it, docs/models/explicit.md "Pre-cut slit (3D)"), w = sqrt(R^2 - b^2) as above:
//  side < 0 (wall lip): as bevelWedge3D, the chisel across the chord, then the lower outline -w; a lip on the
//    plane (a = -R <= -w) stays put;
//  side > 0 (bevel lip), gap = floor - a: the bevel face continued across the chord lifts the lip from the
//    plane, floor = min(w, -R - s tan(alpha)) behind the point (reaction tan(alpha) on the face), then the
//    upper outline w; ahead of the point floor = -R - s tan(beta) (reaction tan(beta)), which meets only a lip
//    dragged below the plane by its tied partner and is continuous with the face at the point.
// So the bevel-side lip opens by R + w (2R on the sharp point's line) and the wall-side lip not at all.
// x: as for bevelWedge3D.
bool bevelSlitWedge3D(const needle::NeedleShape& shape, const needle::NeedlePose& pose, const Eigen::Vector3d& x,
                      int side, needle::NeedleHit& hit, double& axialPerLateral);

// Where the seam whose lips the needle wedges lies: the 2D cut line through the leading point, the 3D plane
// through the needle axis (the cohesive seam), or the 3D node-release slit through the leading point (the
// bevel's sharp point; a cone's apex, on the axis).
enum class LipSeam { Planar, ThroughAxis, ThroughPoint };

// The rule for this tip and seam (2D bevel, 3D bevel through the axis or the point, 3D cone); false for
// other tips.
bool lipWedge(const needle::NeedleShape& shape, const needle::NeedlePose& pose, const Eigen::Vector3d& x, int side,
              LipSeam seam, needle::NeedleHit& hit, double& axialPerLateral);

}  // namespace needlesim::explicit_fe
