#pragma once
// Surface files by format: needlesim reads STL, PLY, OFF (mesh/stl_reader, ply_reader,
// off_reader), Wavefront OBJ (here: vertices and faces; polygons split into fans) and VTK XML
// PolyData (mesh/vtp_reader) itself; only legacy VTK goes to Gmsh's library, and the formats that
// would crash or mislead it are refused with what to write instead.
#include <optional>
#include <string>

#include "needlesim/mesh/closed_surface.hpp"

namespace needlesim::mesh {

// Why Gmsh must not be given this surface file, with what to write instead; nullopt when it may.
// Legacy VTK 5.x (aborts Gmsh 4.8), VTK XML unstructured grids (.vtu: not read; .vtp surfaces
// are read by mesh/vtp_reader).
struct SurfaceFormatProblem {
  std::string problem, allowed;
};
std::optional<SurfaceFormatProblem> surfaceFormatProblem(const std::string& path);

// The surface of a file in a format needlesim reads itself (.stl, .ply, .off, .obj, .vtp), or
// nullopt for legacy VTK (.vtk, read by Gmsh after mesh/legacy_vtk_check); any other extension is an InputError listing the
// formats. Coordinates, counts and triangles are checked (mesh/surface_checks).
std::optional<TriangleSurface> readOwnSurfaceFormat(const std::string& path);

bool isObj(const std::string& path);
// The vertices and faces of a Wavefront OBJ file (v and f records; "f a/b/c ..." takes the vertex
// index, negative indices count from the end; faces of n > 3 vertices are split into n - 2
// triangles). Throws InputError naming the file and line on a malformed record.
TriangleSurface readObj(const std::string& path);

}  // namespace needlesim::mesh
