#pragma once
// Legacy VTK surfaces (.vtk, version 4.2 or older) are read by Gmsh's library; before it sees one,
// needlesim checks what would crash or exhaust it: the header, the POINTS (finite coordinates of
// at most kLargestCoordinate, as many as declared) and the counts of the cell sections (POLYGONS,
// CELLS, LINES, VERTICES, TRIANGLE_STRIPS, CELL_TYPES) against the bytes that follow, in ASCII and
// BINARY files.
#include <string>

namespace needlesim::mesh {

void checkLegacyVtk(const std::string& path);

}  // namespace needlesim::mesh
