// PLY reader: header, then the elements' data in ascii or binary of either byte order.
#include "needlesim/mesh/ply_reader.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <map>
#include <sstream>
#include <vector>

#include "needlesim/mesh/surface_checks.hpp"

namespace needlesim::mesh {

namespace {

const char* kAllowed =
    "a PLY surface: 'ply', 'format ascii|binary_little_endian|binary_big_endian 1.0', a vertex element with float "
    "or double x, y, z, a face element with a list of integer vertex_indices, 'end_header', then the data";

struct Property {
  std::string name, type;  // type: the item type of a list
  bool list = false;
  std::string countType;
};

struct Element {
  std::string name;
  std::uint64_t count = 0;
  int line = 0;
  std::vector<Property> properties;
};

enum class Format { Ascii, Little, Big };

struct Header {
  Format format = Format::Ascii;
  std::vector<Element> elements;
  std::size_t dataStart = 0;  // the byte after end_header's line
  int lines = 0;              // lines of the header
};

int typeSize(const std::string& t) {
  static const std::map<std::string, int> sizes = {
      {"char", 1},  {"int8", 1},  {"uchar", 1}, {"uint8", 1},   {"short", 2},  {"int16", 2},   {"ushort", 2}, {"uint16", 2},
      {"int", 4},   {"int32", 4}, {"uint", 4},  {"uint32", 4},  {"float", 4},  {"float32", 4}, {"double", 8}, {"float64", 8}};
  const auto it = sizes.find(t);
  return it == sizes.end() ? 0 : it->second;
}
bool isFloatType(const std::string& t) { return t == "float" || t == "float32" || t == "double" || t == "float64"; }

std::vector<std::string> words(const std::string& line) {
  std::istringstream in(line);
  std::vector<std::string> w;
  for (std::string s; in >> s;) w.push_back(s);
  return w;
}

Property readProperty(const std::string& path, int line, const std::vector<std::string>& w) {
  Property p;
  const auto bad = [&](const std::string& why) {
    std::string text;
    for (const auto& s : w) text += (text.empty() ? "" : " ") + s;
    return surfaceError(path, line, fmt::format("header line \"{}\": {}", printable(text), why), kAllowed);
  };
  if (w.size() == 5 && w[1] == "list") {
    p.list = true, p.countType = w[2], p.type = w[3], p.name = w[4];
    if (typeSize(p.countType) == 0 || isFloatType(p.countType)) throw bad("a list's count type must be an integer type");
  } else if (w.size() == 3) {
    p.type = w[1], p.name = w[2];
  } else {
    throw bad("a property is 'property type name' or 'property list count_type item_type name'");
  }
  if (typeSize(p.type) == 0) throw bad(fmt::format("\"{}\" is not a PLY type", printable(p.type)));
  return p;
}

Header readHeader(const std::string& path, const std::string& bytes) {
  Header h;
  std::size_t at = 0;
  bool formatSeen = false;
  for (int line = 1;; ++line) {
    const std::size_t end = bytes.find('\n', at);
    if (end == std::string::npos || line > 10000)
      throw surfaceError(path, line, "has no 'end_header' line", kAllowed);
    std::string text = bytes.substr(at, end - at);
    if (!text.empty() && text.back() == '\r') text.pop_back();
    at = end + 1;
    const auto w = words(text);
    if (line == 1) {
      if (w.size() != 1 || w[0] != "ply") throw surfaceError(path, 1, "does not start with the line 'ply'", kAllowed);
      continue;
    }
    if (w.empty() || w[0] == "comment" || w[0] == "obj_info") continue;
    if (w[0] == "end_header") {
      h.dataStart = at;
      h.lines = line;
      break;
    }
    if (w[0] == "format") {
      static const std::map<std::string, Format> formats = {
          {"ascii", Format::Ascii}, {"binary_little_endian", Format::Little}, {"binary_big_endian", Format::Big}};
      if (w.size() != 3 || !formats.count(w[1]) || w[2] != "1.0")
        throw surfaceError(path, line, fmt::format("has format \"{}\"", printable(text)), kAllowed);
      h.format = formats.at(w[1]);
      formatSeen = true;
    } else if (w[0] == "element") {
      char* stop = nullptr;
      const unsigned long long n = w.size() == 3 && w[2].find_first_not_of("0123456789") == std::string::npos && w[2].size() <= 15
                                       ? std::strtoull(w[2].c_str(), &stop, 10)
                                       : std::numeric_limits<unsigned long long>::max();
      if (n == std::numeric_limits<unsigned long long>::max())
        throw surfaceError(path, line, fmt::format("header line \"{}\" is not 'element name count'", printable(text)), kAllowed);
      h.elements.push_back({w[1], n, line, {}});
    } else if (w[0] == "property") {
      if (h.elements.empty()) throw surfaceError(path, line, "has a property before any element", kAllowed);
      h.elements.back().properties.push_back(readProperty(path, line, w));
    } else {
      throw surfaceError(path, line, fmt::format("has the header line \"{}\"", printable(text)), kAllowed);
    }
  }
  if (!formatSeen) throw surfaceError(path, 2, "has no 'format' line", kAllowed);
  return h;
}

// The values of the data part, in order, whatever the format.
class DataReader {
 public:
  DataReader(const std::string& path, const std::string& bytes, const Header& h)
      : path_(path), bytes_(bytes), format_(h.format), at_(h.dataStart), line_(h.lines + 1) {}

  // The next value, of PLY type `type`; false at the end of the data.
  bool next(const std::string& type, double& v) { return format_ == Format::Ascii ? nextText(type, v) : nextBinary(type, v); }
  // Where the reader is: the line (ascii) or 0, and words for a message.
  int line() const { return format_ == Format::Ascii ? line_ : 0; }
  // The line the next value is on (ascii) or 0.
  int nextLine() {
    if (format_ != Format::Ascii) return 0;
    skipSpace();
    return line_;
  }
  std::string where() const { return where(at_); }
  std::string where(std::size_t at) const { return format_ == Format::Ascii ? "" : fmt::format(" (byte {})", at); }
  std::size_t offset() const { return at_; }
  bool atEnd() {
    if (format_ != Format::Ascii) return at_ >= bytes_.size();
    skipSpace();
    return at_ >= bytes_.size();
  }
  std::size_t remaining() const { return bytes_.size() - std::min(at_, bytes_.size()); }

 private:
  void skipSpace() {
    while (at_ < bytes_.size() && std::isspace(static_cast<unsigned char>(bytes_[at_]))) {
      if (bytes_[at_] == '\n') ++line_;
      ++at_;
    }
  }
  bool nextText(const std::string& type, double& v) {
    skipSpace();
    if (at_ >= bytes_.size()) return false;
    std::size_t end = at_;
    while (end < bytes_.size() && !std::isspace(static_cast<unsigned char>(bytes_[end]))) ++end;
    const std::string word = bytes_.substr(at_, end - at_);
    at_ = end;
    char* stop = nullptr;
    v = isFloatType(type) ? std::strtod(word.c_str(), &stop) : static_cast<double>(std::strtoll(word.c_str(), &stop, 10));
    if (word.empty() || *stop != '\0' || (!isFloatType(type) && word.size() > 12))
      throw surfaceError(path_, line_, fmt::format("has \"{}\" where a value of type {} is expected", printable(word), type), kAllowed);
    return true;
  }
  bool nextBinary(const std::string& type, double& v) {
    const std::size_t n = static_cast<std::size_t>(typeSize(type));
    if (remaining() < n) return false;
    unsigned char b[8];
    std::memcpy(b, bytes_.data() + at_, n);
    if (format_ == Format::Big) std::reverse(b, b + n);
    at_ += n;
    v = decode(type, b);
    return true;
  }
  static double decode(const std::string& t, const unsigned char* b) {
    const auto as = [&](auto x) {
      std::memcpy(&x, b, sizeof x);
      return static_cast<double>(x);
    };
    if (t == "char" || t == "int8") return as(std::int8_t{});
    if (t == "uchar" || t == "uint8") return as(std::uint8_t{});
    if (t == "short" || t == "int16") return as(std::int16_t{});
    if (t == "ushort" || t == "uint16") return as(std::uint16_t{});
    if (t == "int" || t == "int32") return as(std::int32_t{});
    if (t == "uint" || t == "uint32") return as(std::uint32_t{});
    if (t == "float" || t == "float32") return as(float{});
    return as(double{});
  }

  const std::string& path_;
  const std::string& bytes_;
  Format format_;
  std::size_t at_;
  int line_;
};

// The fewest bytes one instance of e takes (a face at least a triangle).
double leastBytes(const Element& e, Format f) {
  double n = 0;
  for (const auto& p : e.properties) {
    const double items = p.list && e.name == "face" ? 3 : 0;
    if (f == Format::Ascii) n += 2 * (1 + items);  // a digit and a separator per value
    else n += p.list ? typeSize(p.countType) + items * typeSize(p.type) : typeSize(p.type);
  }
  return std::max(n, 1.0);
}

class PlyReader {
 public:
  PlyReader(const std::string& path, const std::string& bytes) : path_(path), bytes_(bytes), h_(readHeader(path, bytes)), data_(path, bytes, h_) {}

  TriangleSurface read() {
    checkCounts();
    for (const auto& e : h_.elements) {
      for (std::uint64_t i = 0; i < e.count; ++i) {
        if (data_.atEnd())
          throw surfaceError(path_, e.line, fmt::format("the header declares {} {} elements; the data ends after {}", e.count, e.name, i),
                             kAllowed);
        if (e.name == "vertex") readVertex(e, i);
        else if (e.name == "face") readFace(e, i);
        else skip(e, i);
      }
    }
    if (!data_.atEnd())
      throw surfaceError(path_, data_.line(),
                         fmt::format("holds data{} beyond the elements its header declares ({})", data_.where(), declared()), kAllowed);
    checkTriangles(path_, s_, [&](int t) {
      const Origin& o = origins_[t];
      return TriangleOrigin{o.line, fmt::format("face {}{}", o.face, data_.where(o.byte))};
    }, kAllowed);
    return std::move(s_);
  }

 private:
  std::string declared() const {
    std::string s;
    for (const auto& e : h_.elements) s += fmt::format("{}{} {}", s.empty() ? "" : ", ", e.count, e.name);
    return s;
  }
  void checkCounts() {
    const Element* vertex = nullptr;
    const Element* face = nullptr;
    for (const auto& e : h_.elements) {
      if (e.name == "vertex") vertex = &e;
      if (e.name == "face") face = &e;
      const double room = std::floor(static_cast<double>(data_.remaining()) / leastBytes(e, h_.format));
      if (static_cast<double>(e.count) > room)
        throw surfaceError(path_, e.line,
                           fmt::format("the header declares {} {} elements, but the {} bytes of data hold at most {}", e.count, e.name,
                                       data_.remaining(), room),
                           kAllowed);
    }
    if (!vertex || !face) throw surfaceError(path_, h_.lines, "has no vertex or no face element", kAllowed);
    checkTriangleCount(path_, face->line, static_cast<double>(face->count), "faces", kAllowed);
    for (const char* axis : {"x", "y", "z"})
      if (std::none_of(vertex->properties.begin(), vertex->properties.end(),
                       [&](const Property& p) { return p.name == axis && !p.list && isFloatType(p.type); }))
        throw surfaceError(path_, vertex->line, fmt::format("the vertex element has no float or double property {}", axis), kAllowed);
    if (std::none_of(face->properties.begin(), face->properties.end(), [](const Property& p) { return isIndexList(p); }))
      throw surfaceError(path_, face->line, "the face element has no list of integer vertex_indices", kAllowed);
    s_.xyz.reserve(3 * vertex->count);
  }
  static bool isIndexList(const Property& p) {
    return p.list && (p.name == "vertex_indices" || p.name == "vertex_index") && !isFloatType(p.type);
  }
  double value(const std::string& type, const Element& e, std::uint64_t i) {
    double v = 0;
    if (!data_.next(type, v))
      throw surfaceError(path_, data_.line(), fmt::format("the header declares {} {} elements; the data ends inside {} {}", e.count,
                                                          e.name, e.name, i + 1),
                         kAllowed);
    return v;
  }
  void readVertex(const Element& e, std::uint64_t i) {
    double p[3] = {0, 0, 0};
    const int line = data_.nextLine();
    const std::size_t start = data_.offset();
    for (const auto& prop : e.properties) {
      if (prop.list) {
        skipList(prop, e, i);
        continue;
      }
      const double v = value(prop.type, e, i);
      if (prop.name.size() == 1 && prop.name[0] >= 'x' && prop.name[0] <= 'z') p[prop.name[0] - 'x'] = v;
    }
    checkVertex(path_, line, [&] { return fmt::format("vertex {}{}", i, data_.where(start)); }, p, kAllowed);
    s_.xyz.insert(s_.xyz.end(), {p[0], p[1], p[2]});
  }
  void readFace(const Element& e, std::uint64_t i) {
    const int line = data_.nextLine();
    const std::size_t start = data_.offset();
    const std::string where = data_.where(start);
    for (const auto& prop : e.properties) {
      if (!isIndexList(prop)) {
        if (prop.list) skipList(prop, e, i);
        else value(prop.type, e, i);
        continue;
      }
      const double n = value(prop.countType, e, i);
      if (!(n >= 3) || n > static_cast<double>(data_.remaining()))
        throw surfaceError(path_, data_.line(), fmt::format("face {}{} has {} corners", i, where, n),
                           "faces of at least 3 corners; " + std::string(kAllowed));
      std::vector<int> corners;
      for (int k = 0; k < static_cast<int>(n); ++k) {
        const double v = value(prop.type, e, i);
        if (!(v >= 0 && v <= std::numeric_limits<int>::max()))
          throw surfaceError(path_, data_.line(), fmt::format("face {}{} names vertex {:.0f}", i, where, v), kAllowed);
        corners.push_back(static_cast<int>(v));
      }
      for (std::size_t k = 1; k + 1 < corners.size(); ++k) {
        s_.tri.insert(s_.tri.end(), {corners[0], corners[k], corners[k + 1]});
        origins_.push_back({line, i, start});
      }
      checkTriangleCount(path_, data_.line(), static_cast<double>(origins_.size()), "triangles (faces split into triangles)", kAllowed);
    }
  }
  void skipList(const Property& prop, const Element& e, std::uint64_t i) {
    const double n = value(prop.countType, e, i);
    if (!(n >= 0) || n > static_cast<double>(data_.remaining()))
      throw surfaceError(path_, data_.line(), fmt::format("{} {}{}: the list {} has {} items", e.name, i, data_.where(), prop.name, n),
                         kAllowed);
    for (int k = 0; k < static_cast<int>(n); ++k) value(prop.type, e, i);
  }
  void skip(const Element& e, std::uint64_t i) {
    for (const auto& prop : e.properties) {
      if (prop.list) skipList(prop, e, i);
      else value(prop.type, e, i);
    }
  }

  std::string path_;
  const std::string& bytes_;
  Header h_;
  DataReader data_;
  TriangleSurface s_;
  struct Origin {
    int line;
    std::uint64_t face;
    std::size_t byte;
  };
  std::vector<Origin> origins_;
};

}  // namespace

TriangleSurface readPly(const std::string& path) {
  const std::string bytes = readSurfaceBytes(path, kAllowed);
  return PlyReader(path, bytes).read();
}

}  // namespace needlesim::mesh
