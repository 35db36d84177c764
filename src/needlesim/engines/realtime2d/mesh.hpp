#pragma once
// Structured quadrilateral mesh of the 2D tissue rectangle for the real-time
// FE engine (seed 003 section 3.3: a 120 x 80 mm rectangle of ~600 nodes).
// Coordinates: x = depth from the entry face (x = 0), y = lateral (0..width).
// Lateral spacing may be graded so that elements are finest on the needle
// path line y = path_y and grow geometrically towards the sides.
#include <Eigen/Core>
#include <vector>

namespace needlesim::realtime2d {

struct MeshSpec {
  double length = 0.08;   // m, depth (x) extent: entry face to far face
  double width = 0.12;    // m, lateral (y) extent
  int nodes_depth = 21;   // nodes along x
  int nodes_lateral = 31; // nodes along y
  double path_y = 0.06;   // m, lateral position of the refined line (kept on a node row)
  double grading = 1.0;   // ratio coarsest / finest lateral spacing (1 = uniform)
};

// A generated mesh is structured (nx x ny nodes on the lines xs, ys); an imported one
// (imported_mesh.hpp) is not: its quads are the file's quadrilaterals and its triangles as
// collapsed quads (a, b, c, c), and xs, ys are empty.
struct Mesh {
  int nx = 0, ny = 0;                 // nodes along x (depth) and y (lateral); 0 when unstructured
  std::vector<double> xs, ys;         // node coordinates along each direction (structured only)
  Eigen::Matrix2Xd nodes;             // node positions, node id = i * ny + j (structured)
  Eigen::Matrix4Xi quads;             // counter-clockwise node ids
  bool triangles = false;             // every quad is a collapsed triangle (a, b, c, c)
  double extent_x = 0.0, extent_y = 0.0;  // m, largest node coordinates (the corner is at 0, 0)
  bool structured() const { return !xs.empty(); }
  int node(int i, int j) const { return i * ny + j; }
  int nodeCount() const { return static_cast<int>(nodes.cols()); }
  int elementCount() const { return static_cast<int>(quads.cols()); }
  double length() const { return structured() ? xs.back() : extent_x; }
  double width() const { return structured() ? ys.back() : extent_y; }
};

// Reference needle axis and the nodes on it.
struct PathNode {
  int node = 0;      // mesh node id
  double s = 0.0;    // m, reference position along the axis from the entry point
  double offset = 0; // m, lateral distance of the node from the axis line
};

// Builds the mesh; throws needlesim::Error on bad input.
Mesh generateMesh(const MeshSpec& spec);

// Lateral coordinates 0..width with a node at path_y, spacing graded by `grading`.
std::vector<double> gradedCoordinates(double width, double path_y, int nodes, double grading);

}  // namespace needlesim::realtime2d
