#pragma once
// The annular wedge of a hollow bevel needle on a cylindrical cohesive sleeve
// (seed 001 section 3.2: cohesive elements on "the thin cylindrical sleeve along
// the axial direction"; its "custom constraint ... to ensure that the needle tip
// cut along the cohesive surface"; docs/models/cohesive.md "Sleeve seam").
//
// The sleeve (radius r_s, r_i < r_s < r_o) is split into core-side nodes
// (side -1) and outer-side nodes (side +1). The bevel plane reaches radius r_s
// at azimuth theta (cos theta = e_r . bevelSide) at the axial position
// s_e = -(r_s cos theta + R) / tan(alpha) from the tip (the sharp point,
// theta = pi, leads; the heel trails by 2R / tan(alpha)). Once the wall's leading
// edge has passed a node's reference axial station by Delta = s_e - s > 0, the
// core-side node must lie inside r <= max(r_i, r_s - Delta tan(beta)) and the
// outer-side node outside r >= min(r_o, r_s + Delta tan(beta)): a ramp of angle
// beta (kLipRampAngle, 30 deg: the 2D rule's virtual chisel) on the wall's edge
// (tip face, frictionless; the needle takes the axial reaction tan(beta) per unit
// radial force so that its work equals the opening work), then the bore and the
// outer wall (wall friction). The analogue of the 2D bevel lip rule
// (cohesive_wedge.hpp), continuous in s and theta. The ramp line extends ahead of the edge (Delta < 0):
// a core node dragged outwards beyond r_s + |Delta| tan(beta) (or an outer node inwards) is pushed back
// before the edge arrives (without it an intact pair dragged off the sleeve by the bevel's leading
// outer rim met the rule with a jump in depth, chattered and tore the entry elements).
#include <Eigen/Core>

#include "needlesim/needle/surface_mesh.hpp"

namespace needlesim::explicit_fe {

// x: the node's position at its reference axial station; side -1 core, +1 outer; rs the sleeve radius.
// Returns false (hit untouched) for a solid or non-bevel needle, a node behind the needle's base, or a
// node on its allowed side.
// xRef (optional): the node's reference position; its azimuth places the edge (s_e), so the gap depends on the
// current position through r only and the radial push derives from a potential.
bool sleeveWedge(const needle::NeedleShape& shape, const needle::NeedlePose& pose, const Eigen::Vector3d& x, int side,
                 double rs, needle::NeedleHit& hit, double& axialPerLateral, const Eigen::Vector3d* xRef = nullptr);

// Axial position (from the tip, along the axis; <= 0) where the bevel plane crosses radius r at
// azimuth cosine c = e_r . bevelSide: s = -(r c + R) / tan(alpha).
double sleeveEdge(const needle::NeedleShape& shape, double r, double cosTheta);

}  // namespace needlesim::explicit_fe
