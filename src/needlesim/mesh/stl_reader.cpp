// STL reader (ASCII and binary): the triangles with exactly coinciding vertices merged.
#include "needlesim/mesh/stl_reader.hpp"

#include <fmt/format.h>

#include <array>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <unordered_map>
#include <vector>

#include "needlesim/mesh/surface_checks.hpp"
#include "needlesim/mesh/word_lines.hpp"

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
  AsciiStl(const std::string& path, const std::string& text) : path_(path), lines_(path, text, kAllowed) {}

  TriangleSurface read() {
    VertexMerger merge(s_);
    std::vector<int> facetLines;
    bool inSolid = false;
    while (lines_.next()) {
      if (!inSolid) {
        expectKeyword("solid");
        inSolid = true;
      } else if (lines_.words()[0] == "endsolid") {
        inSolid = false;
      } else {
        facetLines.push_back(lines_.line());
        readFacet(merge);
        checkTriangleCount(path_, lines_.line(), static_cast<double>(facetLines.size()), "facets", kAllowed);
      }
    }
    if (inSolid) throw lines_.error("ends inside a solid: 'endsolid' is missing");
    if (facetLines.empty()) throw lines_.error("holds no facets");
    checkTriangles(path_, s_, [&](int t) { return TriangleOrigin{facetLines[t], fmt::format("facet {}", t + 1)}; }, kAllowed);
    return std::move(s_);
  }

 private:
  void expectKeyword(const std::string& keyword, std::size_t numbers = 0, const std::string& second = "") {
    const auto& words = lines_.words();
    const std::size_t first = second.empty() ? 1 : 2;
    if (words[0] != keyword || (!second.empty() && (words.size() < 2 || words[1] != second)) ||
        (keyword != "solid" && words.size() != first + numbers))
      throw lines_.error(fmt::format("has \"{}\" where '{}{}{}' is expected", printable(lines_.joined()), keyword,
                                     second.empty() ? "" : " " + second,
                                     numbers ? fmt::format(" and {} numbers", numbers) : ""));
  }
  void expectLine(const std::string& keyword, std::size_t numbers = 0, const std::string& second = "") {
    if (!lines_.next()) throw lines_.error(fmt::format("ends where '{}' is expected", keyword));
    expectKeyword(keyword, numbers, second);
  }
  void readFacet(VertexMerger& merge) {
    expectKeyword("facet", 3, "normal");
    for (std::size_t i = 2; i < 5; ++i) lines_.number(i);
    expectLine("outer", 0, "loop");
    for (int v = 0; v < 3; ++v) {
      expectLine("vertex", 3);
      const double p[3] = {lines_.number(1), lines_.number(2), lines_.number(3)};
      checkVertex(path_, lines_.line(), [&] { return fmt::format("vertex {} of facet {}", v + 1, s_.triangles() + 1); }, p,
                  kAllowed);
      s_.tri.push_back(merge.add(p));
    }
    expectLine("endloop");
    expectLine("endfacet");
  }

  std::string path_;
  WordLines lines_;
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
