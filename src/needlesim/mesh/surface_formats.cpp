#include "needlesim/mesh/surface_formats.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "needlesim/core/error.hpp"

namespace needlesim::mesh {

namespace {
std::string extensionOf(const std::string& path) {
  std::string e = std::filesystem::path(path).extension().string();
  std::transform(e.begin(), e.end(), e.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return e;
}

InputError objError(const std::string& path, int line, const std::string& problem) {
  return InputError(SourceLocation{path, line, 0}, "tissue.geometry", std::filesystem::path(path).filename().string(),
                    problem, "Wavefront OBJ records 'v x y z' and 'f i j k ...' (1-based or negative vertex indices)");
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

bool isObj(const std::string& path) { return extensionOf(path) == ".obj"; }

TriangleSurface readObj(const std::string& path) {
  std::ifstream in(path);
  TriangleSurface s;
  std::string text;
  for (int line = 1; std::getline(in, text); ++line) {
    std::istringstream record(text);
    std::string kind;
    record >> kind;
    const int vertices = static_cast<int>(s.xyz.size() / 3);
    if (kind == "v") {
      double x = 0, y = 0, z = 0;
      if (!(record >> x >> y >> z)) throw objError(path, line, "vertex record without three coordinates");
      s.xyz.insert(s.xyz.end(), {x, y, z});
    } else if (kind == "f") {
      std::vector<int> corners;
      for (std::string token; record >> token;) corners.push_back(cornerIndex(token, vertices, path, line));
      if (corners.size() < 3) throw objError(path, line, "face with fewer than three corners");
      for (std::size_t k = 1; k + 1 < corners.size(); ++k) s.tri.insert(s.tri.end(), {corners[0], corners[k], corners[k + 1]});
    }
  }
  return s;
}

}  // namespace needlesim::mesh
