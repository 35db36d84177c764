#pragma once
// Hex8 block with a cylindrical cohesive sleeve around the insertion axis
// (seed 001 section 3.2: "the joint surface was inserted into both sides of the
// predetermined crack path, which is the direction of the thin cylindrical
// sleeve along the axial direction"; docs/models/cohesive.md "Sleeve seam").
//
// Cross-section (y, z) as an O-grid: an inner square of half-side 0.4 r_s,
// curved blocks from the square to the circle r = r_s (the core), and
// circle-to-rectangle blocks graded outward to the block faces (seed 001: 0.25
// -> 3 mm). The section is extruded along x (insertion axis, depth from the
// entry face x = 0). Sleeve nodes (on the circle) with x <= sleeveDepth are
// duplicated: the original stays with the core (r < r_s), the copy goes to the
// outer tissue. The first circle station beyond sleeveDepth stays shared (the
// closed end of the sleeve).
#include <Eigen/Core>
#include <array>
#include <utility>
#include <vector>

#include "needlesim/engines/explicit/mesh.hpp"

namespace needlesim::explicit_fe {

struct SleeveMeshSpec {
  double width = 0.0, height = 0.0;  // m, block extent along y and z (centred on z = 0, y = 0)
  double axisY = 0.0;                // m, the insertion axis at (y, z) = (axisY, 0)
  double radius = 0.0;               // m, sleeve radius r_s
  int perQuarter = 4;                // cells per quarter circle (4 x around; inner square perQuarter^2)
  int coreLayers = 2;                // radial cells between the inner square and the circle
  double squareRatio = 0.4;          // inner square half-side / r_s (small: the ring inside the sleeve stays
                                     // well inside the bore when the sleeve is pushed in, cohesive_sleeve.hpp)
  double radialSize = 0.0;           // m, first radial cell outside the circle (0 = the circumferential size)
  double maxSize = 3e-3;             // m, largest radial cell towards the block faces
  double grading = 1.25;             // growth ratio of neighbouring radial cells
  std::vector<double> xs;            // axial stations (depth), increasing, xs[0] = 0 the entry face
  double sleeveDepth = 0.0;          // m, circle nodes with x <= sleeveDepth are split
};

struct SleeveMesh {
  Mesh mesh;
  std::vector<std::pair<int, int>> pairs;  // (core-side original, outer-side copy)
  // zero-thickness quads on the sleeve: mesh node ids (outer copy where split, the shared node
  // where not) and each quad's reference outward radial normal
  std::vector<std::array<int, 4>> quads;
  std::vector<Eigen::Vector3d> quadNormals;
};

// Throws Error (naming the parameter) on a radius that does not fit the block, too few cells,
// or unsorted stations.
SleeveMesh sleeveBlock(const SleeveMeshSpec& spec);

}  // namespace needlesim::explicit_fe
