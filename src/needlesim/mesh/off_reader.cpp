// OFF reader: header, counts, vertices, polygon faces split into fans.
#include "needlesim/mesh/off_reader.hpp"

#include <fmt/format.h>

#include <cmath>
#include <cstdlib>
#include <limits>
#include <sstream>
#include <vector>

#include "needlesim/mesh/surface_checks.hpp"

namespace needlesim::mesh {

namespace {

const char* kAllowed =
    "an OFF surface: the line OFF, the counts 'vertices faces edges', one 'x y z' per vertex, one 'n i1 ... in' "
    "per face (0-based vertex indices), '#' comments";

class OffReader {
 public:
  OffReader(const std::string& path, const std::string& text) : path_(path), text_(text) {}

  TriangleSurface read() {
    readHeader();
    for (long long v = 0; v < vertices_; ++v) readVertex(v);
    for (long long f = 0; f < faces_; ++f) readFace(f);
    if (nextLine())
      throw surfaceError(path_, line_,
                         fmt::format("holds more than the {} vertices and {} faces its counts declare: \"{}\"", vertices_, faces_,
                                     printable(joined())),
                         kAllowed);
    checkTriangles(path_, s_, [&](int t) { return TriangleOrigin{origins_[t].first, fmt::format("face {}", origins_[t].second)}; },
                   kAllowed);
    return std::move(s_);
  }

 private:
  // The next line with something on it (comments removed), split into words; false at the end.
  bool nextLine() {
    while (at_ < text_.size()) {
      std::size_t end = text_.find('\n', at_);
      if (end == std::string::npos) end = text_.size();
      std::string line = text_.substr(at_, end - at_);
      at_ = end + 1;
      ++line_;
      line = line.substr(0, line.find('#'));
      std::istringstream in(line);
      words_.clear();
      for (std::string w; in >> w;) words_.push_back(w);
      if (!words_.empty()) return true;
    }
    return false;
  }
  std::string joined() const {
    std::string s;
    for (const auto& w : words_) s += (s.empty() ? "" : " ") + w;
    return s;
  }
  double number(std::size_t i) const {
    char* end = nullptr;
    const double v = std::strtod(words_[i].c_str(), &end);
    if (end == words_[i].c_str() || *end != '\0')
      throw surfaceError(path_, line_, fmt::format("has \"{}\" where a number is expected", printable(words_[i])), kAllowed);
    return v;
  }
  long long integer(std::size_t i, const std::string& what) const {
    const std::string& w = words_[i];
    if (w.empty() || w.size() > 12 || w.find_first_not_of("0123456789") != std::string::npos)
      throw surfaceError(path_, line_, fmt::format("has \"{}\" where {} (a whole number of at least 0) is expected", printable(w), what),
                         kAllowed);
    return std::atoll(w.c_str());
  }
  void readHeader() {
    if (!nextLine() || words_[0] != "OFF")
      throw surfaceError(path_, line_,
                         words_.empty() ? "is empty"
                                        : fmt::format("starts with \"{}\", not the line OFF", printable(words_.empty() ? "" : words_[0])),
                         kAllowed + std::string(" (COFF, NOFF, STOFF, 4OFF and binary OFF are not read)"));
    words_.erase(words_.begin());
    if (words_.empty() && !nextLine()) throw surfaceError(path_, line_, "ends before its counts", kAllowed);
    if (words_.size() != 3)
      throw surfaceError(path_, line_, fmt::format("has \"{}\" where the counts 'vertices faces edges' are expected", printable(joined())),
                         kAllowed);
    vertices_ = integer(0, "the vertex count");
    faces_ = integer(1, "the face count");
    integer(2, "the edge count");
    // every vertex takes at least 6 bytes ("0 0 0\n"), every face 8 ("3 0 1 2\n")
    const std::size_t rest = text_.size() - std::min(at_, text_.size());
    if (static_cast<double>(vertices_) * 6 + static_cast<double>(faces_) * 8 > static_cast<double>(rest))
      throw surfaceError(path_, line_,
                         fmt::format("declares {} vertices and {} faces, more than the {} bytes after the counts can hold", vertices_,
                                     faces_, rest),
                         kAllowed);
    checkTriangleCount(path_, line_, static_cast<double>(faces_), "faces", kAllowed);
    s_.xyz.reserve(static_cast<std::size_t>(3 * vertices_));
  }
  void readVertex(long long v) {
    if (!nextLine())
      throw surfaceError(path_, line_, fmt::format("declares {} vertices; the file ends after {}", vertices_, v), kAllowed);
    if (words_.size() != 3)
      throw surfaceError(path_, line_, fmt::format("vertex {} is \"{}\", not 'x y z'", v, printable(joined())), kAllowed);
    const double p[3] = {number(0), number(1), number(2)};
    checkVertex(path_, line_, [&] { return fmt::format("vertex {}", v); }, p, kAllowed);
    s_.xyz.insert(s_.xyz.end(), {p[0], p[1], p[2]});
  }
  void readFace(long long f) {
    if (!nextLine())
      throw surfaceError(path_, line_, fmt::format("declares {} faces; the file ends after {}", faces_, f), kAllowed);
    const long long n = integer(0, "the face's corner count");
    if (n < 3 || static_cast<std::size_t>(n) + 1 > words_.size())
      throw surfaceError(path_, line_, fmt::format("face {} has {} corners and {} indices after the count", f, n, words_.size() - 1),
                         "faces of at least 3 corners, each an index; " + std::string(kAllowed));
    std::vector<int> corners;
    for (long long k = 1; k <= n; ++k) {
      const long long i = integer(static_cast<std::size_t>(k), "a vertex index");
      if (i >= vertices_)
        throw surfaceError(path_, line_, fmt::format("face {} names vertex {}; the file has {} (numbered from 0)", f, i, vertices_), kAllowed);
      corners.push_back(static_cast<int>(i));
    }
    for (std::size_t k = 1; k + 1 < corners.size(); ++k) {
      s_.tri.insert(s_.tri.end(), {corners[0], corners[k], corners[k + 1]});
      origins_.push_back({line_, f});
    }
    checkTriangleCount(path_, line_, static_cast<double>(origins_.size()), "triangles (faces split into triangles)", kAllowed);
  }

  std::string path_;
  const std::string& text_;
  std::size_t at_ = 0;
  int line_ = 0;
  std::vector<std::string> words_;
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
