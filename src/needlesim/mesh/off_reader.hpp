#pragma once
// OFF surfaces (Object File Format, as Geomview, MeshLab and CGAL write it) read by needlesim:
// the line "OFF" (the counts may follow on it), the counts "vertices faces edges", one
// "x y z" per vertex, one "n i1 ... in" per face (0-based indices, an optional colour after
// them; polygons split into fans); '#' starts a comment. Variants with colours, normals or
// texture coordinates per vertex (COFF, NOFF, STOFF, 4OFF) and binary OFF are refused.
#include <string>

#include "needlesim/mesh/closed_surface.hpp"

namespace needlesim::mesh {

TriangleSurface readOff(const std::string& path);

}  // namespace needlesim::mesh
