// STL reader (ASCII and binary): the triangles with exactly coinciding vertices merged.
#include "needlesim/mesh/stl_reader.hpp"

#include <fmt/format.h>

#include <array>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <unordered_map>
#include <sstream>
#include <vector>

#include "needlesim/mesh/surface_checks.hpp"

namespace needlesim::mesh {

namespace {

const char* kAllowed =
    "an STL surface: binary (an 80-byte header, the triangle count n, 50 bytes per triangle: 84 + 50 n bytes) or "
    "ASCII (solid, then facet normal / outer loop / three vertex x y z / endloop / endfacet per triangle, endsolid)";

// Adds vertex p, or finds it when an earlier triangle has exactly the same one.
class VertexMerger {
 public:
  explicit VertexMerger(TriangleSurface& s) : s_(s) {}
  int add(const double* p) {
    const Key key{p[0] + 0.0, p[1] + 0.0, p[2] + 0.0};  // -0 and 0 alike
    const auto [at, added] = index_.try_emplace(key, static_cast<int>(s_.xyz.size() / 3));
    if (added) s_.xyz.insert(s_.xyz.end(), {p[0], p[1], p[2]});
    return at->second;
  }

 private:
  using Key = std::array<double, 3>;
  struct Hash {
    std::size_t operator()(const Key& k) const {
      std::size_t h = 0;
      for (double x : k) {
        std::uint64_t bits;
        std::memcpy(&bits, &x, 8);
        h = (h ^ bits) * 0x100000001b3ull;
      }
      return h ^ (h >> 29);
    }
  };
  TriangleSurface& s_;
  std::unordered_map<Key, int, Hash> index_;
};

// ---- binary

TriangleSurface readBinary(const std::string& path, const std::string& bytes) {
  std::uint32_t n = 0;
  std::memcpy(&n, bytes.data() + 80, 4);
  const std::uint64_t expected = 84 + 50 * std::uint64_t(n);
  if (expected != bytes.size())
    throw surfaceError(path, 0,
                       fmt::format("is a binary STL of {} bytes, but its header counts {} triangles, which take 84 + 50 x {} = {} "
                                   "bytes (an ASCII STL starts with 'solid' and has facet records)",
                                   bytes.size(), n, n, expected),
                       kAllowed);
  checkTriangleCount(path, 0, n, "triangles", kAllowed);
  TriangleSurface s;
  VertexMerger merge(s);
  s.tri.reserve(3 * std::size_t(n));
  for (std::uint32_t t = 0; t < n; ++t) {
    const char* record = bytes.data() + 84 + 50 * std::size_t(t);
    for (int v = 0; v < 3; ++v) {
      float f[3];
      std::memcpy(f, record + 12 + 12 * v, 12);
      const double p[3] = {f[0], f[1], f[2]};
      checkVertex(path, 0, [&] { return fmt::format("vertex {} of triangle {} (byte {})", v + 1, t + 1, 84 + 50 * std::size_t(t) + 12 + 12 * v); },
                  p, kAllowed);
      s.tri.push_back(merge.add(p));
    }
  }
  checkTriangles(path, s, [](int t) { return TriangleOrigin{0, fmt::format("triangle {}", t + 1)}; }, kAllowed);
  return s;
}

// ---- ASCII

class AsciiStl {
 public:
  AsciiStl(const std::string& path, const std::string& text) : path_(path), in_(text) {}

  TriangleSurface read() {
    VertexMerger merge(s_);
    std::vector<int> facetLines;
    bool inSolid = false;
    while (next()) {
      if (!inSolid) {
        expectKeyword("solid");
        inSolid = true;
      } else if (words_[0] == "endsolid") {
        inSolid = false;
      } else {
        facetLines.push_back(line_);
        readFacet(merge);
        checkTriangleCount(path_, line_, static_cast<double>(facetLines.size()), "facets", kAllowed);
      }
    }
    if (inSolid) throw surfaceError(path_, line_, "ends inside a solid: 'endsolid' is missing", kAllowed);
    if (facetLines.empty()) throw surfaceError(path_, line_, "holds no facets", kAllowed);
    checkTriangles(path_, s_, [&](int t) { return TriangleOrigin{facetLines[t], fmt::format("facet {}", t + 1)}; }, kAllowed);
    return std::move(s_);
  }

 private:
  // The next line that is not blank, split into words; false at the end of the file.
  bool next() {
    std::string text;
    while (std::getline(in_, text)) {
      ++line_;
      std::istringstream words(text);
      words_.clear();
      for (std::string w; words >> w;) words_.push_back(w);
      if (!words_.empty()) return true;
    }
    return false;
  }
  void expectKeyword(const std::string& keyword, std::size_t numbers = 0, const std::string& second = "") {
    const std::size_t first = second.empty() ? 1 : 2;
    if (words_[0] != keyword || (!second.empty() && (words_.size() < 2 || words_[1] != second)) ||
        (keyword != "solid" && words_.size() != first + numbers))
      throw surfaceError(path_, line_,
                         fmt::format("has \"{}\" where '{}{}{}' is expected", printable(joined()), keyword,
                                     second.empty() ? "" : " " + second, numbers ? fmt::format(" and {} numbers", numbers) : ""),
                         kAllowed);
  }
  void expectLine(const std::string& keyword, std::size_t numbers = 0, const std::string& second = "") {
    if (!next()) throw surfaceError(path_, line_, fmt::format("ends where '{}' is expected", keyword), kAllowed);
    expectKeyword(keyword, numbers, second);
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
  void readFacet(VertexMerger& merge) {
    expectKeyword("facet", 3, "normal");
    for (std::size_t i = 2; i < 5; ++i) number(i);
    expectLine("outer", 0, "loop");
    for (int v = 0; v < 3; ++v) {
      expectLine("vertex", 3);
      const double p[3] = {number(1), number(2), number(3)};
      checkVertex(path_, line_, [&] { return fmt::format("vertex {} of facet {}", v + 1, s_.triangles() + 1); }, p, kAllowed);
      s_.tri.push_back(merge.add(p));
    }
    expectLine("endloop");
    expectLine("endfacet");
  }

  std::string path_;
  std::istringstream in_;
  std::vector<std::string> words_;
  int line_ = 0;
  TriangleSurface s_;
};

// ASCII when the file starts with "solid" and names a facet (or ends its solid) early on: binary
// headers may start with "solid" too.
bool looksAscii(const std::string& bytes) {
  const std::size_t start = bytes.find_first_not_of(" \t\r\n");
  if (start == std::string::npos || bytes.compare(start, 5, "solid") != 0) return false;
  const std::string head = bytes.substr(0, 4096);
  return head.find("facet") != std::string::npos || head.find("endsolid") != std::string::npos;
}

}  // namespace

TriangleSurface readStl(const std::string& path) {
  const std::string bytes = readSurfaceBytes(path, kAllowed);
  std::uint32_t n = 0;
  if (bytes.size() >= 84) std::memcpy(&n, bytes.data() + 80, 4);
  const bool binarySized = bytes.size() >= 84 && 84 + 50 * std::uint64_t(n) == bytes.size();
  if (looksAscii(bytes) && !(binarySized && bytes.find('\0') != std::string::npos)) return AsciiStl(path, bytes).read();
  if (bytes.size() < 84)
    throw surfaceError(path, 0,
                       fmt::format("is {} bytes long: too short for a binary STL (84-byte header) and not an ASCII STL "
                                   "(starting with 'solid')",
                                   bytes.size()),
                       kAllowed);
  return readBinary(path, bytes);
}

}  // namespace needlesim::mesh
