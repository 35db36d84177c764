#pragma once
// A triangulated surface that should bound a body (read from an STL/PLY/VTK/OFF/OBJ file by
// mesh/gmsh_reader): whether it is closed, whether a point lies inside it, and which bodies lie
// directly inside which (an organ holding a tumour: the tumour is a hole of the organ's volume).
#include <array>
#include <string>
#include <vector>

namespace needlesim::mesh {

struct TriangleSurface {
  std::vector<double> xyz;  // x y z per vertex
  std::vector<int> tri;     // three vertex indices per triangle
  int triangles() const { return static_cast<int>(tri.size()) / 3; }
};

// The first edge not shared by exactly two triangles, described with its end points and how
// many triangles use it; "" when every edge is (the surface is closed and manifold).
std::string openEdge(const TriangleSurface& s);

// The surface with every triangle split into four at its edge midpoints, as often as it takes
// for the longest edge to be at most maxEdge (shared edges split alike: the surface stays closed).
TriangleSurface refined(const TriangleSurface& s, double maxEdge);
// The longest edge and the diagonal of the bounding box.
double longestEdge(const TriangleSurface& s);
double boxDiagonal(const TriangleSurface& s);

// Whether point p lies inside the closed surface s (parity of the crossings of a ray).
bool encloses(const TriangleSurface& s, const std::array<double, 3>& p);

// How surface b lies to surface a, judged at up to 64 of b's vertices: all inside a, all
// outside, or some of each (the surfaces cross).
enum class Placement { Outside, Inside, Crossing };
Placement placement(const TriangleSurface& a, const TriangleSurface& b);

// For each surface, the surfaces lying directly inside it (inside it and inside no other
// surface that is itself inside it).
std::vector<std::vector<int>> directlyInside(const std::vector<TriangleSurface>& surfaces);

}  // namespace needlesim::mesh
