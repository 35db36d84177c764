#pragma once
// Meshes for the explicit engine: structured graded blocks in 2D (4-node
// quads or 3-node triangles) and 3D (8-node hexahedra or 4-node tetrahedra),
// refined around the needle path (seed 001 section 3.2: a 0.25 mm core
// graded to 3 mm at the boundary), and imported meshes (mesh/gmsh_reader.hpp).
// Coordinates are stored node-interleaved (x0 y0 [z0] x1 ...), SI metres.
#include <string>
#include <vector>

#include "needlesim/core/error.hpp"
#include "needlesim/mesh/volume_mesh.hpp"
#include "needlesim/scenario/scenario.hpp"

namespace needlesim::explicit_fe {

enum class ElementType { Quad4, Tri3, Hex8, Tet4 };

int nodesPerElement(ElementType t);
int elementDim(ElementType t);
std::string elementName(ElementType t);
ElementType elementTypeFromName(const std::string& name);  // quad4, tri3, hex8, tet4; throws Error

struct Mesh {
  int dim = 2;
  ElementType type = ElementType::Quad4;
  std::vector<double> X;     // reference coordinates, dim per node
  std::vector<int> conn;     // nodesPerElement per element
  std::vector<int> region;   // per element: layer / material index (0 if one material)

  int nodes() const { return static_cast<int>(X.size()) / dim; }
  int elements() const { return static_cast<int>(conn.size()) / nodesPerElement(type); }
  double coord(int node, int i) const { return X[static_cast<std::size_t>(node) * dim + i]; }
};

// Coordinates of [a, b] with a uniform core [c0, c1] of spacing h0, growing by
// `ratio` per element outside it up to hmax; each side is rescaled to fit
// exactly. With c0 >= c1 (no core) the interval is split uniformly with h0.
std::vector<double> gradedCoordinates(double a, double b, double c0, double c1, double h0,
                                      double hmax, double ratio = 1.25);

// Structured block from per-axis coordinate lists (tensor product).
// 2D: Quad4, or Tri3 (each quad split into two along alternating diagonals).
// 3D: Hex8, or Tet4 (each hex split into six tetrahedra, conforming).
Mesh structuredBlock(const std::vector<double>& xs, const std::vector<double>& ys, ElementType type);
Mesh structuredBlock(const std::vector<double>& xs, const std::vector<double>& ys,
                     const std::vector<double>& zs, ElementType type);

// A pre-cut needle path (node-release crack, the G_c -> 0 limit of the
// cohesive zone of seed 001 section 3.3 / seed 004 eq 14): nodes on the seam
// (2D: the line y = offset; 3D: the strip y = offset, |z| < halfWidth) with
// x in [x0, x1] are duplicated; elements on the +y side take the copies.
// Returns the (original, copy) pairs; the solver keeps each pair tied until
// the needle tip reaches it. The seam coordinate must be a grid line.
std::vector<std::pair<int, int>> splitSeam(Mesh& mesh, double offset, double x0, double x1,
                                           double halfWidth = 0.0);
// The seam of splitSeam through an unstructured (imported) mesh, in two steps. snapOntoSeam:
// while an element has two nodes strictly on opposite sides of the seam (2D: the line
// y = offset; 3D: the plane, where the crossing lies in the strip |z| < halfWidth) with the
// crossing at x in [x0, x1], the node nearer the seam moves onto it (else the farther one),
// unless that would leave one of its elements with under a tenth of its area or volume; returns
// the nodes moved. Then
// splitAlongFaces: an element with a node strictly on the needle's side of the plane
// (needleSide +1: y > offset, -1: y < offset) is on that side, every other element on the other;
// each node in the window shared by elements of both sides is duplicated and the + side takes
// the copy. The seam thus runs along element faces on the plane wherever the nodes could move
// and otherwise just beside it on the side away from the needle, so no seam node lies in the
// needle's way. On a mesh with a grid line at the seam both give splitSeam's seam.
int snapOntoSeam(Mesh& mesh, double offset, double x0, double x1, double halfWidth);
std::vector<std::pair<int, int>> splitAlongFaces(Mesh& mesh, double offset, double x0, double x1, double halfWidth,
                                                 int needleSide);
// The longest edge of the elements that reach across the plane y = offset within |z| < halfWidth
// (3D; the local element size along the needle path of an imported mesh).
double largestEdgeAcross(const Mesh& mesh, double offset, double halfWidth);
// Moves the grid line nearest to `value` onto it (keeps the list sorted).
void snapCoordinate(std::vector<double>& xs, double value);

// An imported mesh (mesh/volume_mesh.hpp, read by the scenario layer): its tags,
// in increasing order, become regions 0, 1, ... (layer / material indices).
Mesh fromVolumeMesh(const mesh::VolumeMesh& v);
// An imported geometry placed by the scenario reader, with its elements' regions.
Mesh fromImportedGeometry(const ImportedGeometry& g);

}  // namespace needlesim::explicit_fe
