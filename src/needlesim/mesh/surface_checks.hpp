#pragma once
// What every surface reader (STL, PLY, OFF, OBJ, VTP) refuses the same way: a coordinate that is not
// finite or beyond kLargestCoordinate, a triangle naming no vertex or of no area, more triangles than
// any surface needlesim meshes; and the error naming the file, its line (0 for binary data) and the
// record at fault.
#include <cstdint>
#include <functional>
#include <string>

#include "needlesim/core/error.hpp"
#include "needlesim/mesh/closed_surface.hpp"

namespace needlesim::mesh {

// |x|, |y|, |z| of a vertex at most this, in the file's units (1e9 mm is 1000 km).
inline constexpr double kLargestCoordinate = 1e9;
// Triangles a surface file may hold (meshing refuses more anyway, mesh/gmsh_reader.cpp).
inline constexpr std::size_t kMostSurfaceTriangles = 2'000'000;

// The InputError of a surface file: path:line, field tissue.geometry, the file's name.
InputError surfaceError(const std::string& path, int line, const std::string& problem, const std::string& allowed);

// The whole file; refused when larger than kLargestSurfaceFile bytes or unreadable.
inline constexpr std::uintmax_t kLargestSurfaceFile = std::uintmax_t(1) << 30;
std::string readSurfaceBytes(const std::string& path, const std::string& allowed);

// The file's extension in lower case (".stl").
std::string lowerExtension(const std::string& path);

// Whether every coordinate of vertex p (x y z) is finite and at most kLargestCoordinate in size.
bool isPlausibleVertex(const double* p);
// The error for a vertex that is not: `vertex` says which ("vertex 12", "vertex 2 of facet 7").
[[noreturn]] void refuseVertex(const std::string& path, int line, const std::string& vertex, const double* p,
                               const std::string& allowed);
// Throws refuseVertex's error unless p is plausible; vertexName() is called only then.
template <class Name>
void checkVertex(const std::string& path, int line, Name&& vertexName, const double* p, const std::string& allowed) {
  if (!isPlausibleVertex(p)) refuseVertex(path, line, vertexName(), p, allowed);
}

// Where triangle t of a surface comes from: the file's line (0: none) and words ("face 3").
struct TriangleOrigin {
  int line = 0;
  std::string what;
};

// Throws when a triangle names a vertex the surface does not have, repeats a corner or has no
// area (twice its area at most 1e-12 times its longest edge squared: its corners on a line).
void checkTriangles(const std::string& path, const TriangleSurface& s,
                    const std::function<TriangleOrigin(int)>& origin, const std::string& allowed);

// Throws when a file declares more than kMostSurfaceTriangles triangles (or `count` things that
// would make as many); `what`: "faces", "triangles".
void checkTriangleCount(const std::string& path, int line, double count, const std::string& what,
                        const std::string& allowed);

}  // namespace needlesim::mesh
