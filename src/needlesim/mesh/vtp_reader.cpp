#include "needlesim/mesh/vtp_reader.hpp"

#include <fmt/format.h>
#include <zlib.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "needlesim/core/error.hpp"
#include "needlesim/mesh/surface_checks.hpp"

namespace needlesim::mesh {

namespace {

using Bytes = std::string;

const char* kAllowed =
    "a VTK XML PolyData file (.vtp) as VTK or ParaView write it: little-endian, ascii, binary or appended "
    "data, uncompressed or zlib-compressed, polygons (not strips)";

struct Context {
  std::string path;
  const std::string* text = nullptr;
  int lineOf(std::size_t at) const {
    if (at == std::string::npos || !text || at > text->size()) return 0;
    return 1 + static_cast<int>(std::count(text->begin(), text->begin() + static_cast<std::ptrdiff_t>(at), '\n'));
  }
  InputError error(std::size_t at, const std::string& problem) const {
    return InputError(SourceLocation{path, lineOf(at), 0}, "tissue.geometry", std::filesystem::path(path).filename().string(),
                      problem, kAllowed);
  }
};

// One XML start tag: where it begins and ends, its attributes.
struct Tag {
  std::size_t begin = std::string::npos, end = std::string::npos;  // '<' and one past '>'
  bool selfClosing = false;
  std::map<std::string, std::string> attr;
  std::string get(const std::string& k) const {
    const auto it = attr.find(k);
    return it == attr.end() ? "" : it->second;
  }
};

// The first start tag <name ...> in [from, to), or a Tag with begin npos.
Tag findTag(const Context& c, const std::string& name, std::size_t from, std::size_t to) {
  const std::string& s = *c.text;
  Tag t;
  for (std::size_t at = s.find("<" + name, from); at != std::string::npos && at < to; at = s.find("<" + name, at + 1)) {
    const char next = at + 1 + name.size() < s.size() ? s[at + 1 + name.size()] : '\0';
    if (!std::isspace(static_cast<unsigned char>(next)) && next != '>' && next != '/') continue;
    const std::size_t close = s.find('>', at);
    if (close == std::string::npos || close >= to) throw c.error(at, fmt::format("the <{}> tag is not closed", name));
    t.begin = at;
    t.end = close + 1;
    t.selfClosing = s[close - 1] == '/';
    std::size_t i = at + 1 + name.size();
    while (i < close) {
      while (i < close && (std::isspace(static_cast<unsigned char>(s[i])) || s[i] == '/')) ++i;
      const std::size_t eq = s.find('=', i);
      if (i >= close || eq == std::string::npos || eq >= close) break;
      std::string key = s.substr(i, eq - i);
      key.erase(std::remove_if(key.begin(), key.end(), [](unsigned char ch) { return std::isspace(ch); }), key.end());
      std::size_t q = eq + 1;
      while (q < close && std::isspace(static_cast<unsigned char>(s[q]))) ++q;
      if (q >= close || (s[q] != '"' && s[q] != '\'')) throw c.error(at, fmt::format("attribute {} of <{}> is not quoted", key, name));
      const std::size_t qe = s.find(s[q], q + 1);
      if (qe == std::string::npos || qe > close) throw c.error(at, fmt::format("attribute {} of <{}> is not closed", key, name));
      t.attr[key] = s.substr(q + 1, qe - q - 1);
      i = qe + 1;
    }
    return t;
  }
  return t;
}

// The end of the element opened by t (the position of its </name>).
std::size_t elementEnd(const Context& c, const Tag& t, const std::string& name, std::size_t to) {
  if (t.selfClosing) return t.end;
  const std::size_t e = c.text->find("</" + name, t.end);
  if (e == std::string::npos || e > to) throw c.error(t.begin, fmt::format("<{}> is not closed by </{}>", name, name));
  return e;
}

long long integerAttribute(const Context& c, const Tag& t, const std::string& key, const std::string& element) {
  const std::string v = t.get(key);
  char* end = nullptr;
  errno = 0;
  const long long n = std::strtoll(v.c_str(), &end, 10);
  if (v.empty() || *end != '\0' || errno != 0 || n < 0 || n > (1LL << 31) - 1)
    throw c.error(t.begin, fmt::format("<{}> has no valid {} (\"{}\")", element, key, printable(v)));
  return n;
}

int base64Value(char ch) {
  if (ch >= 'A' && ch <= 'Z') return ch - 'A';
  if (ch >= 'a' && ch <= 'z') return ch - 'a' + 26;
  if (ch >= '0' && ch <= '9') return ch - '0' + 52;
  if (ch == '+') return 62;
  if (ch == '/') return 63;
  return -1;
}

// Decodes base64 text (no white space) of a whole number of 4-character groups; false if invalid.
bool decodeBase64(const char* p, std::size_t n, Bytes& out) {
  if (n % 4 != 0) return false;
  out.clear();
  out.reserve(n / 4 * 3);
  for (std::size_t i = 0; i < n; i += 4) {
    int v[4];
    int pad = 0;
    for (int k = 0; k < 4; ++k) {
      if (p[i + k] == '=' && k >= 2) {
        v[k] = 0;
        ++pad;
      } else {
        if (pad > 0) return false;
        v[k] = base64Value(p[i + k]);
        if (v[k] < 0) return false;
      }
    }
    const std::uint32_t w = (std::uint32_t(v[0]) << 18) | (std::uint32_t(v[1]) << 12) | (std::uint32_t(v[2]) << 6) | std::uint32_t(v[3]);
    out.push_back(static_cast<char>((w >> 16) & 0xff));
    if (pad < 2) out.push_back(static_cast<char>((w >> 8) & 0xff));
    if (pad < 1) out.push_back(static_cast<char>(w & 0xff));
  }
  return true;
}

struct Encoding {
  int headerBytes = 4;  // UInt32 or UInt64
  bool compressed = false;
};

std::uint64_t headerWord(const Bytes& b, std::size_t i, int size) {
  if (size == 4) {
    std::uint32_t v;
    std::memcpy(&v, b.data() + i * 4, 4);
    return v;
  }
  std::uint64_t v;
  std::memcpy(&v, b.data() + i * 8, 8);
  return v;
}

// Reads the data of one binary block (header, then data) from a byte source: raw bytes at a
// position, or base64 text whose header may be encoded apart from the data (VTK encodes the
// header of a compressed array apart, and that of an uncompressed inline array with its data).
class BlockSource {
 public:
  virtual ~BlockSource() = default;
  // The first n decoded bytes of the header, or false when the source is shorter.
  virtual bool header(std::size_t n, Bytes& out) = 0;
  // n bytes of data following a header of h bytes, or false when the source is shorter or invalid.
  virtual bool data(std::size_t h, std::size_t n, Bytes& out) = 0;
};

class RawSource : public BlockSource {
 public:
  RawSource(const std::string& s, std::size_t at) : s_(s), at_(at) {}
  bool header(std::size_t n, Bytes& out) override {
    if (at_ > s_.size() || s_.size() - at_ < n) return false;
    out = s_.substr(at_, n);
    return true;
  }
  bool data(std::size_t h, std::size_t n, Bytes& out) override {
    if (at_ + h > s_.size() || s_.size() - at_ - h < n) return false;
    out = s_.substr(at_ + h, n);
    return true;
  }

 private:
  const std::string& s_;
  std::size_t at_;
};

class Base64Source : public BlockSource {
 public:
  explicit Base64Source(std::string text) : t_(std::move(text)) {}
  bool header(std::size_t n, Bytes& out) override {
    const std::size_t chars = (n + 2) / 3 * 4;
    if (chars > t_.size() || !decodeBase64(t_.data(), chars, out) || out.size() < n) return false;
    out.resize(n);
    return true;
  }
  bool data(std::size_t h, std::size_t n, Bytes& out) override {
    const std::size_t hchars = (h + 2) / 3 * 4;
    const bool apart = h % 3 != 0 && hchars <= t_.size() && t_[hchars - 1] == '=';
    if (apart) {
      const std::size_t chars = (n + 2) / 3 * 4;
      if (t_.size() - hchars < chars || !decodeBase64(t_.data() + hchars, chars, out) || out.size() < n) return false;
      out.resize(n);
      used_ = hchars + chars;
      return true;
    }
    const std::size_t chars = (h + n + 2) / 3 * 4;
    Bytes all;
    if (chars > t_.size() || !decodeBase64(t_.data(), chars, all) || all.size() < h + n) return false;
    out = all.substr(h, n);
    used_ = chars;
    return true;
  }
  // Characters the last data() read, header included, and all there are.
  std::size_t used() const { return used_; }
  std::size_t size() const { return t_.size(); }

 private:
  std::string t_;
  std::size_t used_ = 0;
};

// The uncompressed bytes of one array (expected: its size in bytes).
Bytes readBlock(const Context& c, std::size_t at, BlockSource& src, const Encoding& e, std::size_t expected,
                const std::string& what) {
  const int hb = e.headerBytes;
  Bytes h;
  const auto truncated = [&] { return c.error(at, fmt::format("the {} array is truncated or not valid base64", what)); };
  if (!e.compressed) {
    if (!src.header(hb, h)) throw truncated();
    const std::uint64_t n = headerWord(h, 0, hb);
    if (n != expected)
      throw c.error(at, fmt::format("the {} array holds {} bytes where {} are expected", what, n, expected));
    Bytes out;
    if (!src.data(hb, expected, out)) throw truncated();
    return out;
  }
  if (!src.header(3 * hb, h)) throw truncated();
  const std::uint64_t blocks = headerWord(h, 0, hb), blockSize = headerWord(h, 1, hb), lastSize = headerWord(h, 2, hb);
  const std::uint64_t lastFull = lastSize == 0 ? blockSize : lastSize;
  if (blocks > (1u << 24) || blockSize > (1u << 30) || lastSize > blockSize ||
      (blocks == 0 ? 0 : (blocks - 1) * blockSize + lastFull) != expected)
    throw c.error(at, fmt::format("the compressed {} array's header ({} blocks of {} bytes, the last {}) does not "
                                  "give the {} bytes expected",
                                  what, blocks, blockSize, lastSize, expected));
  const std::size_t headerSize = (3 + blocks) * hb;
  if (!src.header(headerSize, h)) throw truncated();
  std::uint64_t total = 0;
  for (std::uint64_t b = 0; b < blocks; ++b) total += headerWord(h, 3 + b, hb);
  if (total > (std::uint64_t(1) << 40)) throw truncated();
  Bytes packed;
  if (!src.data(headerSize, total, packed)) throw truncated();
  Bytes out(expected, '\0');
  std::size_t from = 0, to = 0;
  for (std::uint64_t b = 0; b < blocks; ++b) {
    const std::uint64_t size = headerWord(h, 3 + b, hb);
    uLongf made = static_cast<uLongf>(b + 1 == blocks ? lastFull : blockSize);
    const uLongf want = made;
    uLong consumed = static_cast<uLong>(size);
    const int rc = uncompress2(reinterpret_cast<Bytef*>(out.data() + to), &made,
                               reinterpret_cast<const Bytef*>(packed.data() + from), &consumed);
    if (rc != Z_OK || made != want)
      throw c.error(at, fmt::format("block {} of the compressed {} array does not inflate to {} bytes (zlib: {})", b + 1,
                                    what, want, zError(rc)));
    if (consumed != size)
      throw c.error(at, fmt::format("block {} of the compressed {} array is {} bytes long, but its header says {}", b + 1,
                                    what, consumed, size));
    from += size;
    to += made;
  }
  return out;
}

int typeSize(const std::string& type) {
  if (type == "Float32" || type == "Int32" || type == "UInt32") return 4;
  if (type == "Float64" || type == "Int64" || type == "UInt64") return 8;
  return 0;
}

double valueAt(const Bytes& b, std::size_t i, const std::string& type) {
  const char* p = b.data() + i * static_cast<std::size_t>(typeSize(type));
  if (type == "Float32") { float v; std::memcpy(&v, p, 4); return v; }
  if (type == "Float64") { double v; std::memcpy(&v, p, 8); return v; }
  if (type == "Int32") { std::int32_t v; std::memcpy(&v, p, 4); return static_cast<double>(v); }
  if (type == "UInt32") { std::uint32_t v; std::memcpy(&v, p, 4); return static_cast<double>(v); }
  if (type == "Int64") { std::int64_t v; std::memcpy(&v, p, 8); return static_cast<double>(v); }
  std::uint64_t v;
  std::memcpy(&v, p, 8);
  return static_cast<double>(v);
}

struct File {
  Context c;
  std::string s;
  std::size_t xmlEnd = 0;                 // where <AppendedData begins (or the end)
  std::size_t appended = std::string::npos;  // the byte after '_'
  bool appendedBase64 = false;
  Encoding enc;
};

// The count values of a <DataArray> as doubles (Float32 values exactly as the float they are).
std::vector<double> readArray(const File& f, const Tag& t, std::size_t count, const std::string& what,
                              const std::vector<std::string>& types) {
  const Context& c = f.c;
  const std::string type = t.get("type");
  if (std::find(types.begin(), types.end(), type) == types.end())
    throw c.error(t.begin, fmt::format("the {} array has type \"{}\"", what, printable(type)));
  const std::string format = t.get("format");
  // zlib inflates at most about 1032 times: a count beyond that of the file's size is not in it
  if (count / 1100 > f.s.size())
    throw c.error(t.begin, fmt::format("the {} array would hold {} values, more than the file can", what, count));
  std::vector<double> v;
  v.reserve(count);
  if (format == "ascii") {
    const std::size_t end = f.s.find('<', t.end);
    std::istringstream in(f.s.substr(t.end, (end == std::string::npos ? f.s.size() : end) - t.end));
    for (std::string word; in >> word;) {
      char* stop = nullptr;
      double x = std::strtod(word.c_str(), &stop);
      if (*stop != '\0') throw c.error(t.begin, fmt::format("the {} array holds \"{}\", not a number", what, printable(word)));
      if (type == "Float32") x = static_cast<float>(x);
      v.push_back(x);
    }
    if (v.size() != count)
      throw c.error(t.begin, fmt::format("the {} array holds {} values where {} are expected", what, v.size(), count));
    return v;
  }
  const std::size_t size = static_cast<std::size_t>(typeSize(type));
  Bytes b;
  if (format == "binary") {
    const std::size_t end = f.s.find('<', t.end);
    std::string text = f.s.substr(t.end, (end == std::string::npos ? f.s.size() : end) - t.end);
    text.erase(std::remove_if(text.begin(), text.end(), [](unsigned char ch) { return std::isspace(ch); }), text.end());
    Base64Source src(std::move(text));
    b = readBlock(c, t.begin, src, f.enc, count * size, what);
    if (src.used() != src.size())
      throw c.error(t.begin, fmt::format("the {} array's base64 text is {} characters long, but its header gives {} bytes, "
                                         "{} characters", what, src.size(), count * size, src.used()));
  } else if (format == "appended") {
    if (f.appended == std::string::npos) throw c.error(t.begin, fmt::format("the {} array is appended, but the file has no <AppendedData>", what));
    const long long offset = integerAttribute(c, t, "offset", "DataArray");
    const std::size_t at = f.appended + static_cast<std::size_t>(offset);
    if (at > f.s.size()) throw c.error(t.begin, fmt::format("the {} array's offset {} lies past the end of the file", what, offset));
    if (f.appendedBase64) {
      std::size_t end = at;
      while (end < f.s.size() && (base64Value(f.s[end]) >= 0 || f.s[end] == '=')) ++end;
      Base64Source src(f.s.substr(at, end - at));
      b = readBlock(c, t.begin, src, f.enc, count * size, what);
    } else {
      RawSource src(f.s, at);
      b = readBlock(c, t.begin, src, f.enc, count * size, what);
    }
  } else {
    throw c.error(t.begin, fmt::format("the {} array has format \"{}\"", what, printable(format)));
  }
  for (std::size_t i = 0; i < count; ++i) v.push_back(valueAt(b, i, type));
  return v;
}

// The <DataArray> named name inside [from, to).
Tag namedArray(const File& f, std::size_t from, std::size_t to, const std::string& name, const std::string& section) {
  for (Tag t = findTag(f.c, "DataArray", from, to); t.begin != std::string::npos; t = findTag(f.c, "DataArray", t.end, to))
    if (t.get("Name") == name) return t;
  throw f.c.error(from, fmt::format("<{}> has no DataArray named {}", section, name));
}

}  // namespace

bool isVtp(const std::string& path) {
  std::string e = std::filesystem::path(path).extension().string();
  std::transform(e.begin(), e.end(), e.begin(), [](unsigned char ch) { return static_cast<char>(std::tolower(ch)); });
  return e == ".vtp";
}

TriangleSurface readVtp(const std::string& path) {
  File f;
  {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream all;
    all << in.rdbuf();
    f.s = all.str();
  }
  f.c.path = path;
  f.c.text = &f.s;
  const Context& c = f.c;
  f.xmlEnd = f.s.find("<AppendedData");
  if (f.xmlEnd == std::string::npos) f.xmlEnd = f.s.size();
  const Tag file = findTag(c, "VTKFile", 0, f.xmlEnd);
  if (file.begin == std::string::npos) throw c.error(0, "is not a VTK XML file (no <VTKFile> element)");
  if (file.get("type") != "PolyData")
    throw c.error(file.begin, fmt::format("is a VTK XML file of type \"{}\", not PolyData (a surface)", printable(file.get("type"))));
  if (file.get("byte_order") == "BigEndian")
    throw c.error(file.begin, "holds big-endian data, which needlesim does not read (write it little-endian)");
  if (const std::string h = file.get("header_type"); h == "UInt64")
    f.enc.headerBytes = 8;
  else if (!h.empty() && h != "UInt32")
    throw c.error(file.begin, fmt::format("has header_type \"{}\"", printable(h)));
  if (const std::string z = file.get("compressor"); z == "vtkZLibDataCompressor")
    f.enc.compressed = true;
  else if (!z.empty())
    throw c.error(file.begin, fmt::format("is compressed with {}, which needlesim does not read", printable(z)));
  if (f.xmlEnd < f.s.size()) {
    const Tag ad = findTag(c, "AppendedData", f.xmlEnd, f.s.size());
    const std::string enc = ad.get("encoding");
    if (enc != "raw" && enc != "base64") throw c.error(ad.begin, fmt::format("has <AppendedData> of encoding \"{}\"", printable(enc)));
    f.appendedBase64 = enc == "base64";
    const std::size_t underscore = f.s.find('_', ad.end);
    if (underscore == std::string::npos) throw c.error(ad.begin, "has <AppendedData> without its leading '_'");
    f.appended = underscore + 1;
  }
  const Tag piece = findTag(c, "Piece", file.end, f.xmlEnd);
  if (piece.begin == std::string::npos) throw c.error(file.begin, "has no <Piece>");
  const std::size_t pieceEnd = elementEnd(c, piece, "Piece", f.xmlEnd);
  const long long points = integerAttribute(c, piece, "NumberOfPoints", "Piece");
  const long long polys = piece.attr.count("NumberOfPolys") ? integerAttribute(c, piece, "NumberOfPolys", "Piece") : 0;
  if (piece.attr.count("NumberOfStrips") && integerAttribute(c, piece, "NumberOfStrips", "Piece") > 0)
    throw c.error(piece.begin, "holds triangle strips, which needlesim does not read (vtkTriangleFilter turns them into triangles)");

  TriangleSurface s;
  const Tag pointsTag = findTag(c, "Points", piece.end, pieceEnd);
  if (pointsTag.begin == std::string::npos) throw c.error(piece.begin, "has no <Points>");
  const Tag xyz = findTag(c, "DataArray", pointsTag.end, elementEnd(c, pointsTag, "Points", pieceEnd));
  if (xyz.begin == std::string::npos) throw c.error(pointsTag.begin, "<Points> has no DataArray");
  if (xyz.attr.count("NumberOfComponents") && xyz.get("NumberOfComponents") != "3")
    throw c.error(xyz.begin, "the points do not have three components");
  s.xyz = readArray(f, xyz, static_cast<std::size_t>(points) * 3, "points", {"Float32", "Float64"});
  const int pointsLine = c.lineOf(xyz.begin);
  for (long long p = 0; p < points; ++p)
    checkVertex(path, pointsLine, [&] { return fmt::format("point {} (numbered from 0)", p); },
                &s.xyz[3 * static_cast<std::size_t>(p)], kAllowed);
  if (polys == 0) return s;
  checkTriangleCount(path, c.lineOf(piece.begin), static_cast<double>(polys), "polygons", kAllowed);

  const Tag polysTag = findTag(c, "Polys", piece.end, pieceEnd);
  if (polysTag.begin == std::string::npos) throw c.error(piece.begin, "has no <Polys>");
  const std::size_t polysEnd = elementEnd(c, polysTag, "Polys", pieceEnd);
  const std::vector<std::string> ints = {"Int32", "Int64", "UInt32", "UInt64"};
  const Tag offsetsTag = namedArray(f, polysTag.end, polysEnd, "offsets", "Polys");
  const auto offsets = readArray(f, offsetsTag, static_cast<std::size_t>(polys), "polygon offsets", ints);
  long long previous = 0;
  for (double o : offsets) {
    if (!(o <= 1e12)) throw c.error(offsetsTag.begin, fmt::format("the polygon offset {} is not in the file", o));
    if (!(o >= static_cast<double>(previous) + 3))
      throw c.error(offsetsTag.begin, fmt::format("the polygon offsets {} and {} leave a polygon of fewer than three corners", previous, o));
    previous = static_cast<long long>(o);
  }
  const Tag connTag = namedArray(f, polysTag.end, polysEnd, "connectivity", "Polys");
  const auto conn = readArray(f, connTag, static_cast<std::size_t>(previous), "polygon connectivity", ints);
  for (double v : conn)
    if (!(v >= 0 && v < static_cast<double>(points)))
      throw c.error(connTag.begin, fmt::format("the polygon connectivity names point {}, of {}", v, points));
  std::size_t begin = 0;
  std::vector<int> polygonOf;
  for (std::size_t p = 0; p < offsets.size(); ++p) {
    const auto end = static_cast<std::size_t>(offsets[p]);
    for (std::size_t k = begin + 1; k + 1 < end; ++k) {
      s.tri.insert(s.tri.end(), {static_cast<int>(conn[begin]), static_cast<int>(conn[k]), static_cast<int>(conn[k + 1])});
      polygonOf.push_back(static_cast<int>(p));
    }
    begin = end;
  }
  checkTriangleCount(path, c.lineOf(connTag.begin), static_cast<double>(polygonOf.size()), "triangles (polygons split into triangles)",
                     kAllowed);
  checkTriangles(path, s, [&](int t) { return TriangleOrigin{c.lineOf(connTag.begin), fmt::format("polygon {} (numbered from 0)", polygonOf[t])}; },
                 kAllowed);
  return s;
}

}  // namespace needlesim::mesh
