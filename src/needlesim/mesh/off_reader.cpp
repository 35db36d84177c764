// OFF reader: header, counts, vertices, polygon faces split into fans.
#include "needlesim/mesh/off_reader.hpp"

#include <fmt/format.h>

#include <cmath>
#include <cstdlib>
#include <limits>
#include <vector>

#include "needlesim/mesh/surface_checks.hpp"
#include "needlesim/mesh/word_lines.hpp"

namespace needlesim::mesh {

namespace {

const char* kAllowed =
    "an OFF surface: the line OFF, the counts 'vertices faces edges', one 'x y z' per vertex, one 'n i1 ... in' "
    "per face (0-based vertex indices), '#' comments";

class OffReader {
 public:
  OffReader(const std::string& path, const std::string& text) : path_(path), lines_(path, text, kAllowed, '#') {}

  TriangleSurface read() {
    readHeader();
    for (long long v = 0; v < vertices_; ++v) readVertex(v);
    for (long long f = 0; f < faces_; ++f) readFace(f);
    if (lines_.next())
      throw lines_.error(fmt::format("holds more than the {} vertices and {} faces its counts declare: \"{}\"", vertices_,
                                     faces_, printable(lines_.joined())));
    checkTriangles(path_, s_, [&](int t) { return TriangleOrigin{origins_[t].first, fmt::format("face {}", origins_[t].second)}; },
                   kAllowed);
    return std::move(s_);
  }

 private:
  void readHeader() {
    if (!lines_.next() || lines_.words()[0] != "OFF")
      throw lines_.error(lines_.words().empty()
                             ? "is empty"
                             : fmt::format("starts with \"{}\", not the line OFF", printable(lines_.words()[0])),
                         kAllowed + std::string(" (COFF, NOFF, STOFF, 4OFF and binary OFF are not read)"));
    std::size_t first = 1;  // the counts may follow OFF on its line
    if (lines_.words().size() == 1) {
      if (!lines_.next()) throw lines_.error("ends before its counts");
      first = 0;
    }
    if (lines_.words().size() != first + 3)
      throw lines_.error(fmt::format("has \"{}\" where the counts 'vertices faces edges' are expected", printable(lines_.joined())));
    vertices_ = lines_.count(first, "the vertex count");
    faces_ = lines_.count(first + 1, "the face count");
    lines_.count(first + 2, "the edge count");
    // every vertex takes at least 6 bytes ("0 0 0\n"), every face 8 ("3 0 1 2\n")
    const std::size_t rest = lines_.bytesLeft();
    if (static_cast<double>(vertices_) * 6 + static_cast<double>(faces_) * 8 > static_cast<double>(rest))
      throw lines_.error(fmt::format("declares {} vertices and {} faces, more than the {} bytes after the counts can hold",
                                     vertices_, faces_, rest));
    checkTriangleCount(path_, lines_.line(), static_cast<double>(faces_), "faces", kAllowed);
    s_.xyz.reserve(static_cast<std::size_t>(3 * vertices_));
  }
  void readVertex(long long v) {
    if (!lines_.next()) throw lines_.error(fmt::format("declares {} vertices; the file ends after {}", vertices_, v));
    if (lines_.words().size() != 3)
      throw lines_.error(fmt::format("vertex {} is \"{}\", not 'x y z'", v, printable(lines_.joined())));
    const double p[3] = {lines_.number(0), lines_.number(1), lines_.number(2)};
    checkVertex(path_, lines_.line(), [&] { return fmt::format("vertex {}", v); }, p, kAllowed);
    s_.xyz.insert(s_.xyz.end(), {p[0], p[1], p[2]});
  }
  void readFace(long long f) {
    if (!lines_.next()) throw lines_.error(fmt::format("declares {} faces; the file ends after {}", faces_, f));
    const auto& words = lines_.words();
    const long long n = lines_.count(0, "the face's corner count");
    if (n < 3 || static_cast<std::size_t>(n) + 1 > words.size())
      throw lines_.error(fmt::format("face {} has {} corners and {} indices after the count", f, n, words.size() - 1),
                         "faces of at least 3 corners, each an index; " + std::string(kAllowed));
    std::vector<int> corners;
    for (long long k = 1; k <= n; ++k) {
      const long long i = lines_.count(static_cast<std::size_t>(k), "a vertex index");
      if (i >= vertices_)
        throw lines_.error(fmt::format("face {} names vertex {}; the file has {} (numbered from 0)", f, i, vertices_));
      corners.push_back(static_cast<int>(i));
    }
    for (std::size_t k = 1; k + 1 < corners.size(); ++k) {
      s_.tri.insert(s_.tri.end(), {corners[0], corners[k], corners[k + 1]});
      origins_.push_back({lines_.line(), f});
    }
    checkTriangleCount(path_, lines_.line(), static_cast<double>(origins_.size()), "triangles (faces split into triangles)",
                       kAllowed);
  }

  std::string path_;
  WordLines lines_;
  long long vertices_ = 0, faces_ = 0;
  TriangleSurface s_;
  std::vector<std::pair<int, long long>> origins_;  // line and face of each triangle
};

}  // namespace

TriangleSurface readOff(const std::string& path) {
  const std::string text = readSurfaceBytes(path, kAllowed);
  return OffReader(path, text).read();
}

}  // namespace needlesim::mesh
