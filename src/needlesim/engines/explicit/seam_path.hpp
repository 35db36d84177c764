#pragma once
// A seam along a user-given path (docs/models/cohesive.md "Crack path"): the
// cohesive interface needs the crack faces on element edges, so instead of
// cutting the mesh along the path, a straight grid line is split (splitSeam)
// and then moved onto the path by a smooth vertical morph of the 2D mesh
// (nodes within `band` of the line follow it with weight 1 - |y - line|/band).
#include <Eigen/Core>
#include <vector>

#include "needlesim/engines/explicit/mesh.hpp"

namespace needlesim::explicit_fe {

// Path height at x: linear interpolation of the polyline (x increasing), constant
// beyond its ends. Throws Error for fewer than 2 points or non-increasing x.
double pathHeight(const std::vector<Eigen::Vector2d>& path, double x);

// Moves every node of the 2D mesh by dy = w (pathHeight(x) - lineY), w = max(0, 1 -
// |y - lineY| / band): the grid line y = lineY lands on the path, nodes beyond `band`
// stay. Throws Error if the morph would fold an element (a path steeper or farther
// from the line than the band allows: |d path / dx| and |path - lineY| must stay below
// the band's scale).
// plateau > 0: nodes within `plateau` of the line follow it fully (w = 1), the weight then falls
// linearly to 0 at `band` (the refined core around the seam moves with the path).
void morphOntoPath(Mesh& mesh, double lineY, const std::vector<Eigen::Vector2d>& path, double band,
                   double plateau = 0.0);

}  // namespace needlesim::explicit_fe
