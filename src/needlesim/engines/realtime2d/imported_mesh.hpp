#pragma once
// An imported 2D mesh (tissue.geometry, scenario/tissue_geometry.hpp) as the real-time 2D
// engine's mesh: quadrilaterals as they are, triangles as collapsed quadrilaterals (a, b, c, c),
// the standard degenerate bilinear element (its 2 x 2 Gauss points stay inside the triangle
// and it reproduces every linear displacement field, so it passes the patch test). The
// mesh is unstructured: the needle path is the line of nodes nearest the axis.
#include <Eigen/Core>
#include <vector>

#include "needlesim/engines/realtime2d/mesh.hpp"
#include "needlesim/scenario/scenario.hpp"

namespace needlesim::realtime2d {

// The geometry's mesh moved by `shift` (centred tissue frame -> mesh coordinates); elements
// counter-clockwise. Throws SolverError on an element type other than tri3 or quad4.
Mesh importedMesh(const ImportedGeometry& geometry, const Eigen::Vector2d& shift);

// Held nodes, as the generated block holds every side but the entry face: the geometry's
// supported far side and the nodes of boundary edges facing across the path (outward
// normal within 45 deg of +-y).
std::vector<bool> importedHeld(const ImportedGeometry& geometry);

// The path of an unstructured mesh: free nodes within half their local element size of the
// axis line through `entry` along `t`, by position along the axis from the entry point
// (s >= 0), thinned so that consecutive nodes lie at least 0.3 local element sizes apart
// (the nearer to the line kept). Each node is tied at its lateral offset.
std::vector<PathNode> pathNearAxis(const Mesh& mesh, const std::vector<bool>& held, const Eigen::Vector2d& entry,
                                   const Eigen::Vector2d& t);

// The path pathNearAxis gives on the geometry of a block of `width` (its corner shift), with the
// frame's entry point (centred tissue frame) and axis; for the step guard.
std::vector<PathNode> importedPath(const ImportedGeometry& geometry, double width, const Eigen::Vector2d& entry,
                                   const Eigen::Vector2d& axis);

// Position along the needle axis (from the frame's entry point) where the axis leaves the
// geometry for the last time; `axis` in the tissue frame.
double exitAlongAxis(const ImportedGeometry& geometry, const Eigen::Vector2d& entry, const Eigen::Vector2d& axis);

}  // namespace needlesim::realtime2d
