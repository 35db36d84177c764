#pragma once
// Gmsh .msh format 4.1 ASCII into a mesh::VolumeMesh: the elements of the
// highest dimension (first-order triangles, quads, tetrahedra or hexahedra, one
// type), in file order; nodes in file order; each element's physical tag (or its
// entity tag when the entity belongs to no physical group). Lower-dimensional
// elements (points, lines, faces of a volume mesh) are skipped. Throws InputError
// naming the file, the section and the value.
#include <string>

#include "needlesim/mesh/volume_mesh.hpp"

namespace needlesim::mesh {

VolumeMesh readGmsh(const std::string& path);

}  // namespace needlesim::mesh
