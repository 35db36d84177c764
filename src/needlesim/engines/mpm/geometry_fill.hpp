#pragma once
// An imported tissue geometry (tissue.geometry, scenario.hpp ImportedGeometry) as mpm material
// points and held grid nodes. docs/models/mpm.md "Imported geometry".
#include <array>
#include <vector>

#include "needlesim/engines/mpm/mpm_solver.hpp"
#include "needlesim/scenario/scenario.hpp"

namespace needlesim::mpm {

// Per point of `lattice` (solver frame = tissue frame + shift): the region of the tetrahedron of
// the geometry's mesh that holds it (ImportedGeometry::region), or -1 outside the mesh. A point on
// a face shared by two elements takes the one listed first. Each element scatters itself to the
// lattice points of its bounding box, so the lattice is the bucket grid of the point location.
std::vector<int> latticeRegions(const ImportedGeometry& geometry, const Lattice& lattice, const Vec3& shift);

// The grid nodes to hold for the geometry's supported side: those within two grid cells of a
// boundary facet whose nodes are all supported, on or outside its plane (the generated block's
// fixed exit face holds the nodes on and beyond it the same way).
std::vector<std::array<int, 3>> heldGridNodes(const ImportedGeometry& geometry, const MpmConfig& config,
                                              const Vec3& shift);

}  // namespace needlesim::mpm
