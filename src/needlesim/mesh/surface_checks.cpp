// Checks shared by the surface readers: finite, bounded coordinates; triangles that name vertices
// of the surface and have an area; a bounded number of triangles.
#include "needlesim/mesh/surface_checks.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace needlesim::mesh {

InputError surfaceError(const std::string& path, int line, const std::string& problem, const std::string& allowed) {
  return InputError(SourceLocation{path, line, 0}, "tissue.geometry", std::filesystem::path(path).filename().string(),
                    problem, allowed);
}

std::string readSurfaceBytes(const std::string& path, const std::string& allowed) {
  std::error_code ec;
  const std::uintmax_t size = std::filesystem::file_size(path, ec);
  if (ec) throw surfaceError(path, 0, "cannot be read: " + ec.message(), allowed);
  if (size > kLargestSurfaceFile)
    throw surfaceError(path, 0, fmt::format("is {} bytes long, more than the {} a surface file may have", size, kLargestSurfaceFile),
                       "a coarser surface (decimate it); " + allowed);
  std::ifstream in(path, std::ios::binary);
  std::ostringstream all;
  all << in.rdbuf();
  if (!in && !in.eof()) throw surfaceError(path, 0, "cannot be read", allowed);
  return all.str();
}

std::string lowerExtension(const std::string& path) {
  std::string e = std::filesystem::path(path).extension().string();
  std::transform(e.begin(), e.end(), e.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return e;
}

bool isPlausibleVertex(const double* p) {
  for (int k = 0; k < 3; ++k)
    if (!(std::abs(p[k]) <= kLargestCoordinate)) return false;  // NaN fails too
  return true;
}

void refuseVertex(const std::string& path, int line, const std::string& vertex, const double* p, const std::string& allowed) {
  int k = 0;
  while (k < 2 && std::abs(p[k]) <= kLargestCoordinate) ++k;
  const std::string value = std::isnan(p[k]) ? "nan" : std::isinf(p[k]) ? (p[k] > 0 ? "inf" : "-inf") : fmt::format("{:g}", p[k]);
  throw surfaceError(path, line, fmt::format("{} has {} = {}", vertex, "xyz"[k], value),
                     fmt::format("finite coordinates of at most {:g} in size (file units); {}", kLargestCoordinate, allowed));
}

namespace {
double distance2(const double* a, const double* b) {
  double d = 0.0;
  for (int k = 0; k < 3; ++k) d += (a[k] - b[k]) * (a[k] - b[k]);
  return d;
}

double twiceArea(const double* a, const double* b, const double* c) {
  const double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, v[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
  const double n[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
  return std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
}
}  // namespace

void checkTriangles(const std::string& path, const TriangleSurface& s,
                    const std::function<TriangleOrigin(int)>& origin, const std::string& allowed) {
  const long long vertices = static_cast<long long>(s.xyz.size() / 3);
  for (int t = 0; t < s.triangles(); ++t) {
    const int* c = &s.tri[static_cast<std::size_t>(t) * 3];
    for (int k = 0; k < 3; ++k)
      if (c[k] < 0 || c[k] >= vertices) {
        const auto o = origin(t);
        throw surfaceError(path, o.line, fmt::format("{} names vertex {}; the file has {} (numbered from 0)", o.what, c[k], vertices),
                           allowed);
      }
    if (c[0] == c[1] || c[1] == c[2] || c[0] == c[2]) {
      const auto o = origin(t);
      throw surfaceError(path, o.line, fmt::format("{} is degenerate: it has corner vertex {} twice", o.what, c[0] == c[1] || c[0] == c[2] ? c[0] : c[1]),
                         "triangles of three distinct corners with a non-zero area; " + allowed);
    }
    const double* a = &s.xyz[3 * static_cast<std::size_t>(c[0])];
    const double* b = &s.xyz[3 * static_cast<std::size_t>(c[1])];
    const double* d = &s.xyz[3 * static_cast<std::size_t>(c[2])];
    const double longest2 = std::max({distance2(a, b), distance2(b, d), distance2(a, d)});
    if (twiceArea(a, b, d) <= 1e-12 * longest2 || longest2 == 0.0) {
      const auto o = origin(t);
      throw surfaceError(path, o.line,
                         fmt::format("{} is degenerate: its corners ({:g}, {:g}, {:g}), ({:g}, {:g}, {:g}), ({:g}, {:g}, {:g}) "
                                     "lie on one line or coincide",
                                     o.what, a[0], a[1], a[2], b[0], b[1], b[2], d[0], d[1], d[2]),
                         "triangles of three distinct corners with a non-zero area; " + allowed);
    }
  }
}

void checkTriangleCount(const std::string& path, int line, double count, const std::string& what,
                        const std::string& allowed) {
  if (count > static_cast<double>(kMostSurfaceTriangles))
    throw surfaceError(path, line, fmt::format("declares {:.0f} {}: more than the {} triangles a surface may have", count, what,
                                               kMostSurfaceTriangles),
                       "a coarser surface (decimate it, e.g. in MeshLab or ParaView); " + allowed);
}

}  // namespace needlesim::mesh
