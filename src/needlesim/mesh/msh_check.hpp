#pragma once
// Gmsh .msh files checked before Gmsh's library reads them, so that a malformed file is an
// InputError naming the file, the line (ASCII) or byte (binary) and what is wrong instead of
// Gmsh's own message, an allocation failure or a crash: $MeshFormat first (version 2.x or 4.1,
// ASCII or binary, 8-byte reals), every section closed by its $End line, $Nodes and $Elements
// present once, every count non-negative and no larger than the bytes that follow can hold,
// blocks adding up to the declared totals, element types Gmsh numbers 1 to 31 with their node
// counts, elements naming only nodes of $Nodes, and every node coordinate finite and at most
// kLargestCoordinate (mesh/surface_checks.hpp) in size, naming the node's tag.
#include <string>

#include "needlesim/mesh/volume_mesh.hpp"

namespace needlesim::mesh {

bool isMsh(const std::string& path);

void checkMshFile(const std::string& path);

// The node coordinates of a mesh read from `path` (a .msh, or a script Gmsh meshed): finite and at
// most kLargestCoordinate in size, else an InputError naming the node (1-based, in the order the
// elements use them).
void checkMeshCoordinates(const std::string& path, const VolumeMesh& m);

}  // namespace needlesim::mesh
