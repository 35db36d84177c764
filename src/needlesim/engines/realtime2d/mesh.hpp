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

struct Mesh {
  int nx = 0, ny = 0;                 // nodes along x (depth) and y (lateral)
  std::vector<double> xs, ys;         // node coordinates along each direction
  Eigen::Matrix2Xd nodes;             // node positions, node id = i * ny + j
  Eigen::Matrix4Xi quads;             // counter-clockwise node ids
  int node(int i, int j) const { return i * ny + j; }
  int nodeCount() const { return nx * ny; }
  int elementCount() const { return static_cast<int>(quads.cols()); }
  double length() const { return xs.back(); }
  double width() const { return ys.back(); }
};

// Builds the mesh; throws needlesim::Error on bad input.
Mesh generateMesh(const MeshSpec& spec);

// Lateral coordinates 0..width with a node at path_y, spacing graded by `grading`.
std::vector<double> gradedCoordinates(double width, double path_y, int nodes, double grading);

}  // namespace needlesim::realtime2d
