#include "needlesim/mesh/surface_formats.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "needlesim/core/error.hpp"
#include "needlesim/mesh/legacy_vtk_check.hpp"
#include "needlesim/mesh/off_reader.hpp"
#include "needlesim/mesh/ply_reader.hpp"
#include "needlesim/mesh/stl_reader.hpp"
#include "needlesim/mesh/surface_checks.hpp"
#include "needlesim/mesh/vtp_reader.hpp"

namespace needlesim::mesh {

namespace {
std::string extensionOf(const std::string& path) { return lowerExtension(path); }

const char* kObjAllowed = "Wavefront OBJ records 'v x y z' and 'f i j k ...' (1-based or negative vertex indices)";

InputError objError(const std::string& path, int line, const std::string& problem) {
  return surfaceError(path, line, problem, kObjAllowed);
}

// The vertex index of one face corner ("7", "7/2", "7//3", "-1") as a 0-based index.
int cornerIndex(const std::string& token, int vertices, const std::string& path, int line) {
  int i = 0;
  try {
    std::size_t used = 0;
    i = std::stoi(token.substr(0, token.find('/')), &used);
  } catch (const std::exception&) {
    throw objError(path, line, fmt::format("face corner '{}' is not a vertex index", printable(token)));
  }
  const int k = i > 0 ? i - 1 : vertices + i;
  if (i == 0 || k < 0 || k >= vertices)
    throw objError(path, line, fmt::format("face corner {} names no vertex (the file has {} so far)", i, vertices));
  return k;
}
}  // namespace

std::optional<SurfaceFormatProblem> surfaceFormatProblem(const std::string& path) {
  const std::string e = extensionOf(path);
  if (e == ".vtu")
    return SurfaceFormatProblem{"is a VTK XML unstructured grid, not a surface needlesim reads",
                                "its surface as VTK XML PolyData (.vtp: in ParaView Extract Surface, then File > Save "
                                "Data), legacy VTK (.vtk, version 4.2 or older) or STL"};
  if (e != ".vtk") return std::nullopt;
  std::ifstream in(path, std::ios::binary);
  std::string header;
  std::getline(in, header);
  const auto at = header.find("Version");
  const double version = at == std::string::npos ? 0.0 : std::atof(header.c_str() + at + 7);
  if (version >= 5.0)
    return SurfaceFormatProblem{fmt::format("is legacy VTK version {:g}, which Gmsh's library cannot read", version),
                                "legacy VTK version 4.2 or older (meshio: file_format=\"vtk42\"), or STL"};
  return std::nullopt;
}

std::optional<TriangleSurface> readOwnSurfaceFormat(const std::string& path) {
  const std::string e = extensionOf(path);
  if (e == ".stl") return readStl(path);
  if (e == ".ply") return readPly(path);
  if (e == ".off") return readOff(path);
  if (e == ".obj") return readObj(path);
  if (e == ".vtp") return readVtp(path);
  if (e == ".vtk") {
    checkLegacyVtk(path);
    return std::nullopt;
  }
  throw surfaceError(path, 0, fmt::format("has the extension \"{}\", which is not a surface format needlesim reads", printable(e)),
                     "a closed surface as .stl (ASCII or binary), .ply, .off, .obj, .vtp (VTK XML PolyData) or legacy "
                     ".vtk (version 4.2 or older)");
}

bool isObj(const std::string& path) { return extensionOf(path) == ".obj"; }

TriangleSurface readObj(const std::string& path) {
  std::istringstream in(readSurfaceBytes(path, kObjAllowed));
  TriangleSurface s;
  std::vector<int> lineOf;  // of each triangle
  std::string text;
  for (int line = 1; std::getline(in, text); ++line) {
    std::istringstream record(text);
    std::string kind;
    record >> kind;
    const int vertices = static_cast<int>(s.xyz.size() / 3);
    if (kind == "v") {
      double x = 0, y = 0, z = 0;
      if (!(record >> x >> y >> z)) throw objError(path, line, "vertex record without three coordinates (finite numbers)");
      const double p[3] = {x, y, z};
      checkVertex(path, line, [&] { return fmt::format("vertex {}", vertices + 1); }, p, kObjAllowed);
      s.xyz.insert(s.xyz.end(), {x, y, z});
    } else if (kind == "f") {
      std::vector<int> corners;
      for (std::string token; record >> token;) corners.push_back(cornerIndex(token, vertices, path, line));
      if (corners.size() < 3) throw objError(path, line, "face with fewer than three corners");
      for (std::size_t k = 1; k + 1 < corners.size(); ++k) {
        s.tri.insert(s.tri.end(), {corners[0], corners[k], corners[k + 1]});
        lineOf.push_back(line);
      }
      checkTriangleCount(path, line, static_cast<double>(lineOf.size()), "triangles (faces split into triangles)", kObjAllowed);
    }
  }
  checkTriangles(path, s, [&](int t) { return TriangleOrigin{lineOf[t], "the face"}; }, kObjAllowed);
  return s;
}

}  // namespace needlesim::mesh
