#pragma once
// The boundary of a volume mesh and the geometry of its elements: facets used by one element only
// (edges of a 2D mesh, faces of a 3D one), with their outward normals; element measures and
// centroids; the first crossing of a ray with the boundary.
#include <array>
#include <optional>
#include <vector>

#include "needlesim/mesh/volume_mesh.hpp"

namespace needlesim::mesh {

using Point = std::array<double, 3>;

struct Facet {
  std::vector<int> nodes;  // 2 (edge), 3 (triangle) or 4 (quadrilateral)
  int element = 0;         // the element it bounds
  Point normal{};          // outward unit normal (2D: in the x-y plane)
  Point centroid{};
};

// Facets that belong to exactly one element.
std::vector<Facet> boundaryFacets(const VolumeMesh& m);

Point nodePoint(const VolumeMesh& m, int n);      // z = 0 for a 2D mesh
Point elementCentroid(const VolumeMesh& m, int e);  // mean of its nodes
// Signed area (2D) or volume (3D): positive for the node order Gmsh writes (counter-clockwise
// triangles and quads, positively oriented tetrahedra and hexahedra).
double elementMeasure(const VolumeMesh& m, int e);
// The same from the corner points of a triangle or quadrilateral (dim 2, in the x-y plane), a
// tetrahedron or a hexahedron (dim 3), in Gmsh's node order.
double cornerMeasure(int dim, const std::vector<Point>& corners);

// Distance along the ray `from + t dir` (dir a unit vector) to its first crossing with a
// boundary facet at t >= 0; none when it misses. 2D meshes: the ray's x-y part.
std::optional<double> firstCrossing(const VolumeMesh& m, const std::vector<Facet>& boundary, const Point& from,
                                    const Point& dir);

}  // namespace needlesim::mesh
