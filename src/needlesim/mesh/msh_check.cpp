// Structural check of Gmsh .msh files (formats 2 and 4.1, ASCII and binary) before Gmsh reads them.
#include "needlesim/mesh/msh_check.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <string_view>
#include <unordered_set>
#include <vector>

#include "needlesim/mesh/surface_checks.hpp"

namespace needlesim::mesh {

namespace {

const char* kAllowed =
    "a Gmsh mesh file as Gmsh or meshio write it: $MeshFormat (2.2 or 4.1, ASCII or binary), then sections such as "
    "$Nodes ... $EndNodes and $Elements ... $EndElements with counts that match their data";

// Nodes of Gmsh element types 1..31 (0: unknown).
int nodesOfType(long long type) {
  static const std::array<int, 32> n = {0, 2, 3, 4, 4, 8, 6, 5, 3, 6, 9, 10, 27, 18, 14, 1,
                                        8, 20, 15, 13, 9, 10, 12, 15, 15, 21, 4, 5, 6, 20, 35, 56};
  return type >= 1 && type <= 31 ? n[static_cast<std::size_t>(type)] : 0;
}

class MshScanner {
 public:
  MshScanner(const std::string& path, const std::string& bytes) : path_(path), b_(bytes) {}

  void check() {
    readFormat();
    bool nodes = false, elements = false;
    for (std::string_view line; nextNonBlank(line);) {
      if (line.empty() || line[0] != '$')
        throw error(lineStart_, fmt::format("has \"{}\" where a section ($Name) begins", printable(line)));
      const std::string name(line.substr(1));
      if (name == "Nodes" || name == "Elements") {
        bool& seen = name == "Nodes" ? nodes : elements;
        if (seen) throw error(lineStart_, fmt::format("has a second ${} section", name));
        if (name == "Elements" && !nodes) throw error(lineStart_, "has $Elements before $Nodes");
        seen = true;
        if (name == "Nodes") v4_ ? nodes4() : nodes2();
        else v4_ ? elements4() : elements2();
        expectEnd(name);
      } else if (name == "PhysicalNames") {
        physicalNames();
        expectEnd(name);
      } else if (name == "Entities" && v4_) {
        entities4();
        expectEnd(name);
      } else if (isDataSection(name)) {
        throw error(lineStart_, fmt::format("holds a ${} section, which needlesim does not read", name) +
                                    " (save the mesh alone: nodes, elements, entities and physical names)");
      } else if (name.starts_with("End")) {
        throw error(lineStart_, fmt::format("has ${} where no ${} section is open", name, name.substr(3)));
      } else {
        skipSection(name);
      }
    }
    if (!nodes || !elements) throw error(b_.size(), fmt::format("has no ${} section", nodes ? "Elements" : "Nodes"));
  }

 private:
  // ---- positions and errors
  InputError error(std::size_t at, const std::string& problem) const {
    const bool text = !binary_ || at < dataStart_;
    int line = 0;
    if (text) line = 1 + static_cast<int>(std::count(b_.begin(), b_.begin() + static_cast<std::ptrdiff_t>(std::min(at, b_.size())), '\n'));
    return surfaceError(path_, line, text ? problem : fmt::format("{} (byte {})", problem, at), kAllowed);
  }
  std::size_t left() const { return b_.size() - std::min(at_, b_.size()); }

  // ---- text
  bool nextLine(std::string_view& line) {
    if (at_ >= b_.size()) return false;
    lineStart_ = at_;
    std::size_t end = b_.find('\n', at_);
    if (end == std::string::npos) end = b_.size();
    line = std::string_view(b_).substr(at_, end - at_);
    while (!line.empty() && (line.back() == '\r' || line.back() == ' ' || line.back() == '\t')) line.remove_suffix(1);
    while (!line.empty() && (line.front() == ' ' || line.front() == '\t')) line.remove_prefix(1);
    at_ = end + 1;
    return true;
  }
  bool nextNonBlank(std::string_view& line) {
    while (nextLine(line))
      if (!line.empty()) return true;
    return false;
  }
  std::string_view expectLine(const std::string& what) {
    std::string_view line;
    if (!nextNonBlank(line)) throw error(b_.size(), fmt::format("ends where {} is expected", what));
    return line;
  }
  static std::vector<std::string_view> words(std::string_view line) {
    std::vector<std::string_view> w;
    std::size_t i = 0;
    while (i < line.size()) {
      while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
      const std::size_t b = i;
      while (i < line.size() && line[i] != ' ' && line[i] != '\t') ++i;
      if (i > b) w.push_back(line.substr(b, i - b));
    }
    return w;
  }
  long long integer(std::string_view w, const std::string& what) const {
    const bool sign = !w.empty() && w[0] == '-';
    if (w.size() == std::size_t(sign) || w.size() > 18 || w.find_first_not_of("0123456789", sign ? 1 : 0) != std::string_view::npos)
      throw error(lineStart_, fmt::format("has \"{}\" where {} (a whole number) is expected", printable(w), what));
    return std::atoll(std::string(w).c_str());
  }
  double real(std::string_view w) const {
    const std::string s(w);
    char* end = nullptr;
    const double v = std::strtod(s.c_str(), &end);
    if (s.empty() || *end != '\0') throw error(lineStart_, fmt::format("has \"{}\" where a number is expected", printable(w)));
    return v;
  }
  // A count read from text: at least 0 and at most what the rest of the file can hold at `least` bytes each.
  long long count(std::string_view w, const std::string& what, double least) const {
    const long long n = integer(w, what);
    if (n < 0 || static_cast<double>(n) * least > static_cast<double>(left()))
      throw error(lineStart_, fmt::format("declares {} {}, {}", n, what,
                                          n < 0 ? "a negative count" : fmt::format("more than the {} bytes that follow can hold", left())));
    return n;
  }
  std::vector<std::string_view> expectWords(std::size_t n, const std::string& what) {
    const auto w = words(expectLine(what));
    if (w.size() != n)
      throw error(lineStart_, fmt::format("has {} values where {} ({} values) is expected", w.size(), what, n));
    return w;
  }

  // ---- binary
  template <class T>
  T raw(const std::string& what) {
    if (left() < sizeof(T)) throw error(at_, fmt::format("ends inside {}", what));
    T v;
    std::memcpy(&v, b_.data() + at_, sizeof(T));
    at_ += sizeof(T);
    return v;
  }
  // A count read from binary data, bounded as count() does.
  std::uint64_t binaryCount(std::uint64_t n, const std::string& what, double least) const {
    if (static_cast<double>(n) * least > static_cast<double>(left()))
      throw error(at_, fmt::format("declares {} {}, more than the {} bytes that follow can hold", n, what, left()));
    return n;
  }

  // ---- sections
  void readFormat() {
    if (expectLine("$MeshFormat") != "$MeshFormat") throw error(lineStart_, "does not start with $MeshFormat");
    const auto w = expectWords(3, "the format line 'version file-type data-size'");
    const std::string version(w[0]);
    v4_ = version == "4.1";
    if (!v4_ && version != "2" && version != "2.0" && version != "2.1" && version != "2.2")
      throw error(lineStart_, fmt::format("has format version {}", printable(version)) +
                                  (version == "4" || version == "4.0" ? " (Gmsh 4.0: save it again as 4.1 or 2.2)" : ""));
    const long long type = integer(w[1], "the file type (0 ASCII, 1 binary)"), size = integer(w[2], "the data size");
    if ((type != 0 && type != 1) || size != 8)
      throw error(lineStart_, fmt::format("has file type {} and data size {}", type, size) + " (0 or 1, and 8 expected)");
    binary_ = type == 1;
    if (binary_) {
      if (raw<std::int32_t>("the byte-order mark") != 1) throw error(at_ - 4, "has binary data of another byte order");
      dataStart_ = at_;
    }
    std::string_view line;
    if (!nextNonBlank(line) || line != "$EndMeshFormat") throw error(lineStart_, "has no $EndMeshFormat after the format line");
    if (binary_) dataStart_ = at_;
  }
  void expectEnd(const std::string& name) {
    std::string_view line;
    const std::size_t at = at_;
    if (!nextNonBlank(line) || line != "$End" + name)
      throw error(at, fmt::format("has no $End{} where its ${} data ends", name, name));
  }
  void skipSection(const std::string& name) {
    const std::size_t from = at_;
    for (std::size_t at = b_.find("$End" + name, from); at != std::string::npos; at = b_.find("$End" + name, at + 1))
      if (at > 0 && b_[at - 1] == '\n') {
        at_ = at;
        std::string_view line;
        nextLine(line);
        if (line == "$End" + name) return;
      }
    throw error(from - 1, fmt::format("opens ${} but never closes it with $End{}", printable(name), printable(name)));
  }

  void refuseNode(long long tag, const double* p, std::size_t at) const {
    int k = 0;
    while (k < 2 && std::abs(p[k]) <= kLargestCoordinate) ++k;
    throw error(at, fmt::format("node {} has {} = {}", tag, "xyz"[k], std::isnan(p[k]) ? "nan" : fmt::format("{:g}", p[k])) +
                        fmt::format(" (coordinates must be finite and at most {:g} in size)", kLargestCoordinate));
  }
  void addNode(long long tag, const double* p, std::size_t at) {
    if (!isPlausibleVertex(p)) refuseNode(tag, p, at);
    if (tag < 1) throw error(at, fmt::format("has node tag {}", tag) + " (tags are 1 or more)");
    nodeTags_.insert(tag);
  }
  void usesNode(long long tag, long long element, std::size_t at) const {
    if (!nodeTags_.count(tag)) throw error(at, fmt::format("element {} uses node {}, which $Nodes does not define", element, tag));
  }
  int elementNodes(long long type, std::size_t at) const {
    const int n = nodesOfType(type);
    if (n == 0) throw error(at, fmt::format("has elements of type {}", type) + " (Gmsh types 1 to 31 are read)");
    return n;
  }

  // Sections Gmsh reads that a tissue mesh has no use for, whose counts needlesim does not check.
  static bool isDataSection(const std::string& name) {
    for (const char* d : {"NodeData", "ElementData", "ElementNodeData", "InterpolationScheme", "Periodic", "GhostElements",
                          "PartitionedEntities", "Parametrizations"})
      if (name == d) return true;
    return false;
  }

  // $PhysicalNames (text in every format): a count, then 'dimension tag "name"' per group.
  void physicalNames() {
    const long long n = count(expectWords(1, "the number of physical names")[0], "physical names", 8);
    for (long long i = 0; i < n; ++i) {
      const std::string_view line = expectLine("a physical name");
      const auto w = words(line);
      const std::size_t open = line.find('"');
      if (w.size() < 3 || open == std::string_view::npos || line.back() != '"' || open == line.size() - 1 || line.size() > 250)
        throw error(lineStart_, fmt::format("has \"{}\" where 'dimension tag \"name\"' (at most 250 characters) is expected",
                                            printable(line)));
      const long long dim = integer(w[0], "a dimension"), tag = integer(w[1], "a physical tag");
      if (dim < 0 || dim > 3 || tag < 1 || tag > std::numeric_limits<std::int32_t>::max())
        throw error(lineStart_, fmt::format("physical name {} has dimension {} and tag {}", i + 1, dim, tag) +
                                    " (dimension 0 to 3, tag 1 to 2147483647)");
    }
  }

  // $Entities of format 4.1: points, curves, surfaces, volumes, each with its physical tags (and
  // bounding entities but for points); the lists' lengths bounded by the bytes that follow.
  void entities4() {
    std::array<std::uint64_t, 4> counts{};
    if (binary_) {
      for (auto& c : counts) c = binaryCount(raw<std::uint64_t>("the entity counts"), "entities", 36);
    } else {
      const auto w = expectWords(4, "the entity counts 'points curves surfaces volumes'");
      for (int k = 0; k < 4; ++k) counts[k] = static_cast<std::uint64_t>(count(w[k], "entities", 8));
    }
    for (int kind = 0; kind < 4; ++kind)
      for (std::uint64_t i = 0; i < counts[kind]; ++i) binary_ ? binaryEntity(kind) : textEntity(kind);
  }
  void binaryEntity(int kind) {
    raw<std::int32_t>("an entity");
    const std::size_t reals = kind == 0 ? 3 : 6;
    if (left() < 8 * reals) throw error(at_, "ends inside an entity");
    at_ += 8 * reals;
    for (int list = 0; list < (kind == 0 ? 1 : 2); ++list) {
      const auto n = binaryCount(raw<std::uint64_t>("an entity"), list == 0 ? "physical tags" : "bounding entities", 4);
      at_ += 4 * static_cast<std::size_t>(n);
    }
  }
  void textEntity(int kind) {
    const auto w = words(expectLine("an entity"));
    const std::size_t reals = kind == 0 ? 3 : 6;
    std::size_t at = 1 + reals;
    for (int list = 0; list < (kind == 0 ? 1 : 2); ++list) {
      if (at >= w.size()) throw error(lineStart_, fmt::format("an entity line has {} values, too few", w.size()));
      const long long n = integer(w[at], "a count of tags");
      if (n < 0 || static_cast<std::size_t>(n) > w.size() - at - 1)
        throw error(lineStart_, fmt::format("an entity line declares {} tags where {} values follow", n, w.size() - at - 1));
      at += 1 + static_cast<std::size_t>(n);
    }
    if (at != w.size()) throw error(lineStart_, fmt::format("an entity line has {} values where {} are expected", w.size(), at));
  }

  void nodes2() {
    if (binary_) {
      const long long n = count(expectWords(1, "the node count")[0], "nodes", 28);
      for (long long i = 0; i < n; ++i) {
        const std::size_t at = at_;
        const auto tag = raw<std::int32_t>("a node");
        const double p[3] = {raw<double>("a node"), raw<double>("a node"), raw<double>("a node")};
        addNode(tag, p, at);
      }
      return;
    }
    const long long n = count(expectWords(1, "the node count")[0], "nodes", 8);
    for (long long i = 0; i < n; ++i) {
      const auto w = words(expectLine(fmt::format("node {} of {}", i + 1, n)));
      if (w.size() != 4) throw error(lineStart_, fmt::format("node {} of {} is not 'tag x y z'", i + 1, n));
      const double p[3] = {real(w[1]), real(w[2]), real(w[3])};
      addNode(integer(w[0], "a node tag"), p, lineStart_);
    }
  }
  void elements2() {
    if (binary_) {
      const long long n = count(expectWords(1, "the element count")[0], "elements", 12);
      for (long long read = 0; read < n;) {
        const std::size_t at = at_;
        const auto type = raw<std::int32_t>("an element block"), many = raw<std::int32_t>("an element block"),
                   tags = raw<std::int32_t>("an element block");
        const int nodes = elementNodes(type, at);
        if (many < 1 || many > n - read || tags < 0 || tags > 100)
          throw error(at, fmt::format("has an element block of {} elements with {} tags ({} of {} elements read)", many, tags, read, n));
        binaryCount(static_cast<std::uint64_t>(many), "elements", 4.0 * (1 + tags + nodes));
        for (int e = 0; e < many; ++e) {
          const auto tag = raw<std::int32_t>("an element");
          at_ += 4 * static_cast<std::size_t>(tags);
          for (int k = 0; k < nodes; ++k) usesNode(raw<std::int32_t>("an element"), tag, at);
        }
        read += many;
      }
      return;
    }
    const long long n = count(expectWords(1, "the element count")[0], "elements", 8);
    for (long long i = 0; i < n; ++i) {
      const auto w = words(expectLine(fmt::format("element {} of {}", i + 1, n)));
      if (w.size() < 3) throw error(lineStart_, fmt::format("element {} of {} is not 'tag type tag-count tags... nodes...'", i + 1, n));
      const long long tag = integer(w[0], "an element tag"), tags = integer(w[2], "the element's tag count");
      const int nodes = elementNodes(integer(w[1], "an element type"), lineStart_);
      if (tags < 0 || tags > 100 || w.size() != static_cast<std::size_t>(3 + tags + nodes))
        throw error(lineStart_, fmt::format("element {} has {} values; its type and {} tags need {}", tag, w.size(), tags, 3 + tags + nodes));
      for (std::size_t k = 3; k < static_cast<std::size_t>(3 + tags); ++k) integer(w[k], "an element's tag");
      for (std::size_t k = static_cast<std::size_t>(3 + tags); k < w.size(); ++k) usesNode(integer(w[k], "a node tag"), tag, lineStart_);
    }
  }

  // Reads the four numbers opening a 4.1 $Nodes or $Elements: blocks and total.
  std::pair<std::uint64_t, std::uint64_t> header4(const std::string& things, double leastEach) {
    if (binary_) {
      const std::size_t at = at_;
      const auto blocks = raw<std::uint64_t>("the section header"), total = raw<std::uint64_t>("the section header");
      raw<std::uint64_t>("the section header"), raw<std::uint64_t>("the section header");
      at_ = at + 32;
      binaryCount(blocks, "blocks", 20);
      return {blocks, binaryCount(total, things, leastEach)};
    }
    const auto w = expectWords(4, "'blocks " + things + " min-tag max-tag'");
    return {static_cast<std::uint64_t>(count(w[0], "blocks", 8)), static_cast<std::uint64_t>(count(w[1], things, leastEach))};
  }
  // The four numbers opening a block: dimension, entity, parametric or type, count.
  std::array<long long, 4> block4(const std::string& things, std::uint64_t left) {
    std::array<long long, 4> v{};
    if (binary_) {
      for (int k = 0; k < 3; ++k) v[k] = raw<std::int32_t>("a block header");
      const auto n = raw<std::uint64_t>("a block header");
      if (n > left) throw error(at_ - 8, fmt::format("has a block of {} {} where {} remain of the declared total", n, things, left));
      v[3] = static_cast<long long>(n);
    } else {
      const auto w = expectWords(4, "a block header 'dimension entity " + std::string(things == "nodes" ? "parametric" : "type") + " count'");
      for (int k = 0; k < 4; ++k) v[k] = integer(w[k], "a block header value");
      if (v[3] < 0 || static_cast<std::uint64_t>(v[3]) > left)
        throw error(lineStart_, fmt::format("has a block of {} {} where {} remain of the declared total", v[3], things, left));
    }
    if (v[0] < 0 || v[0] > 3) throw error(at_, fmt::format("has a block of dimension {}", v[0]));
    return v;
  }
  void nodes4() {
    const auto [blocks, total] = header4("nodes", binary_ ? 32 : 8);
    std::uint64_t seen = 0;
    for (std::uint64_t b = 0; b < blocks; ++b) {
      const auto h = block4("nodes", total - seen);
      const long long n = h[3], values = 3 + (h[2] ? h[0] : 0);
      if (h[2] != 0 && h[2] != 1) throw error(at_, fmt::format("has a node block with parametric = {}", h[2]));
      std::vector<long long> tags;
      tags.reserve(static_cast<std::size_t>(n));
      for (long long i = 0; i < n; ++i) {
        if (binary_) tags.push_back(static_cast<long long>(raw<std::uint64_t>("a node tag")));
        else tags.push_back(integer(words(expectLine("a node tag"))[0], "a node tag"));
      }
      for (long long i = 0; i < n; ++i) {
        double p[3];
        std::size_t at = at_;
        if (binary_) {
          for (long long k = 0; k < values; ++k) {
            const double v = raw<double>("node coordinates");
            if (k < 3) p[k] = v;
          }
        } else {
          const auto w = words(expectLine("node coordinates"));
          at = lineStart_;
          if (static_cast<long long>(w.size()) != values)
            throw error(lineStart_, fmt::format("node {} has {} coordinates where {} are expected", tags[i], w.size(), values));
          for (int k = 0; k < 3; ++k) p[k] = real(w[k]);
        }
        addNode(tags[i], p, at);
      }
      seen += static_cast<std::uint64_t>(n);
    }
    if (seen != total) throw error(at_, fmt::format("declares {} nodes; its blocks hold {}", total, seen));
  }
  void elements4() {
    const auto [blocks, total] = header4("elements", binary_ ? 16 : 4);
    std::uint64_t seen = 0;
    for (std::uint64_t b = 0; b < blocks; ++b) {
      const std::size_t blockAt = at_;
      const auto h = block4("elements", total - seen);
      const int nodes = elementNodes(h[2], binary_ ? blockAt : lineStart_);
      if (binary_) binaryCount(static_cast<std::uint64_t>(h[3]), "elements", 8.0 * (1 + nodes));
      for (long long e = 0; e < h[3]; ++e) {
        if (binary_) {
          const std::size_t at = at_;
          const auto tag = static_cast<long long>(raw<std::uint64_t>("an element"));
          for (int k = 0; k < nodes; ++k) usesNode(static_cast<long long>(raw<std::uint64_t>("an element")), tag, at);
          continue;
        }
        const auto w = words(expectLine("an element"));
        if (w.size() != static_cast<std::size_t>(1 + nodes))
          throw error(lineStart_, fmt::format("an element of type {} has {} values where {} are expected", h[2], w.size(), 1 + nodes));
        const long long tag = integer(w[0], "an element tag");
        for (int k = 1; k <= nodes; ++k) usesNode(integer(w[k], "a node tag"), tag, lineStart_);
      }
      seen += static_cast<std::uint64_t>(h[3]);
    }
    if (seen != total) throw error(at_, fmt::format("declares {} elements; its blocks hold {}", total, seen));
  }

  std::string path_;
  const std::string& b_;
  std::size_t at_ = 0, lineStart_ = 0, dataStart_ = std::string::npos;
  bool binary_ = false, v4_ = false;
  std::unordered_set<long long> nodeTags_;
};

}  // namespace

bool isMsh(const std::string& path) { return lowerExtension(path) == ".msh"; }

void checkMshFile(const std::string& path) {
  const std::string bytes = readSurfaceBytes(path, kAllowed);
  MshScanner(path, bytes).check();
}

void checkMeshCoordinates(const std::string& path, const VolumeMesh& m) {
  for (int n = 0; n < m.nodes(); ++n) {
    double p[3] = {0, 0, 0};
    for (int k = 0; k < m.dim; ++k) p[k] = m.X[static_cast<std::size_t>(n) * m.dim + k];
    checkVertex(path, 0, [&] { return fmt::format("node {} (in the order the elements use them)", n + 1); }, p,
                "a mesh whose nodes lie at finite coordinates");
  }
}

}  // namespace needlesim::mesh
