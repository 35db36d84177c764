#pragma once
// STL surfaces, ASCII and binary, read by needlesim (not Gmsh): vertices that coincide exactly are
// merged so a closed surface stays closed; every malformed record is an InputError naming the
// file and the line (ASCII) or triangle (binary).
#include <string>

#include "needlesim/mesh/closed_surface.hpp"

namespace needlesim::mesh {

// A binary STL is 84 + 50 n bytes for the n triangles its header counts; an ASCII STL is
// "solid name", then per triangle "facet normal nx ny nz", "outer loop", three "vertex x y z",
// "endloop", "endfacet", and "endsolid" (several solids follow one another).
TriangleSurface readStl(const std::string& path);

}  // namespace needlesim::mesh
