#pragma once
// PLY surfaces (Stanford polygon files) read by needlesim (not Gmsh): ascii, binary_little_endian
// and binary_big_endian; the x, y, z of the vertex element (float or double) and the faces'
// vertex_indices lists (integers; polygons split into fans); other elements and properties are
// read past. Every count of the header is checked against the bytes the file holds before
// anything is allocated; every problem is an InputError naming the file and the line (ascii) or
// the element and byte (binary).
#include <string>

#include "needlesim/mesh/closed_surface.hpp"

namespace needlesim::mesh {

TriangleSurface readPly(const std::string& path);

}  // namespace needlesim::mesh
