#pragma once
// VTK XML PolyData surfaces (.vtp), which Gmsh 4.8's library does not read: the points and the
// polygons (split into fans) of the first piece, in every encoding VTK writes (ascii, inline
// base64, appended raw or base64; uncompressed or zlib-compressed; header_type UInt32 or UInt64).
#include <string>

#include "needlesim/mesh/closed_surface.hpp"

namespace needlesim::mesh {

bool isVtp(const std::string& path);
// The points and polygons of a .vtp file (polygons of n > 3 corners split into n - 2 triangles;
// vertices and lines ignored). Throws InputError naming the file (and the line of the element at
// fault) on anything else: another dataset type, big-endian data, triangle strips, another
// compressor, truncated or corrupt arrays, connectivity naming no point.
TriangleSurface readVtp(const std::string& path);

}  // namespace needlesim::mesh
