#include "needlesim/io/binary_state.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <fstream>
#include <iterator>

#include "needlesim/core/error.hpp"

namespace needlesim::io {
namespace {
constexpr std::string_view kMagic = kStateFileMagic;
constexpr std::string_view kAllowed = "a state file written by this needlesim version; delete it to start afresh";
}  // namespace

std::uint64_t fnv1a64(std::string_view bytes, std::uint64_t h) {
  for (const char c : bytes) {
    h ^= static_cast<unsigned char>(c);
    h *= 0x100000001b3ull;
  }
  return h;
}

void BinaryWriter::table(const Table& t) {
  tag("table");
  pod(static_cast<std::uint64_t>(t.columns().size()));
  for (const auto& c : t.columns()) {
    str(c.name);
    str(c.unit);
  }
  std::vector<double> data;
  data.reserve(t.rows() * t.columns().size());
  for (std::size_t r = 0; r < t.rows(); ++r)
    for (std::size_t c = 0; c < t.columns().size(); ++c) data.push_back(t.at(r, c));
  vec(data);
}

std::string BinaryReader::str() {
  const auto n = pod<std::uint64_t>();
  if (n > buf_.size() - pos_) fail("truncated (a text runs past the end of the file)");
  std::string s = buf_.substr(pos_, static_cast<std::size_t>(n));
  pos_ += static_cast<std::size_t>(n);
  return s;
}

void BinaryReader::tag(std::string_view name) {
  const std::size_t at = pos_;
  const auto n = pod<std::uint64_t>();
  if (n > 64 || n > buf_.size() - pos_ || std::string_view(buf_).substr(pos_, static_cast<std::size_t>(n)) != name)
    fail(fmt::format("section '{}' expected at byte {} but not found (another layout or a damaged file)", name, at));
  pos_ += static_cast<std::size_t>(n);
}

Table BinaryReader::table() {
  tag("table");
  const auto nc = pod<std::uint64_t>();
  if (nc > 100000) fail("a table with an impossible number of columns (damaged file)");
  std::vector<Column> cols;
  for (std::uint64_t c = 0; c < nc; ++c) {
    Column col;
    col.name = str();
    col.unit = str();
    cols.push_back(std::move(col));
  }
  Table t(cols);
  const auto data = vec<double>();
  if (nc == 0 ? !data.empty() : data.size() % nc != 0) fail("a table whose values do not fill its rows (damaged file)");
  std::vector<double> row(static_cast<std::size_t>(nc));
  for (std::size_t r = 0; nc > 0 && r < data.size() / nc; ++r) {
    std::copy_n(data.begin() + static_cast<std::ptrdiff_t>(r * nc), nc, row.begin());
    t.addRow(row);
  }
  return t;
}

void BinaryReader::fail(const std::string& problem) const {
  throw InputError(SourceLocation{origin_, 0, 0}, "", "", problem, std::string(kAllowed));
}

void BinaryReader::mismatch(std::string_view what, std::uint64_t got, std::uint64_t want) const {
  fail(fmt::format("holds {} {} but this run has {}; it belongs to another set-up", got, what, want));
}

std::string frameState(std::string_view kind, std::uint32_t version, std::string_view payload) {
  BinaryWriter w;
  std::string out(kMagic);
  w.str(kind);
  w.pod(version);
  w.pod(static_cast<std::uint64_t>(payload.size()));
  out += w.bytes();
  out.append(payload.data(), payload.size());
  const std::uint64_t sum = fnv1a64(out);
  out.append(reinterpret_cast<const char*>(&sum), sizeof sum);
  return out;
}

BinaryReader readStateFile(const std::filesystem::path& file, std::string_view kind, std::uint32_t version) {
  const std::string name = file.string();
  std::ifstream in(file, std::ios::binary);
  if (!in)
    throw InputError(SourceLocation{name, 0, 0}, "", "", "cannot be read (missing or not readable)",
                     "the file an earlier run wrote");
  std::string bytes((std::istreambuf_iterator<char>(in)), {});
  BinaryReader head(bytes, name);
  if (bytes.size() < kMagic.size() || std::string_view(bytes).substr(0, kMagic.size()) != kMagic)
    head.fail(bytes.size() < kMagic.size() ? "truncated (shorter than its header)" : "is not a needlesim state file");
  BinaryReader r(bytes.substr(kMagic.size()), name);
  const std::string k = r.str();
  if (k != kind) r.fail(fmt::format("is a '{}' state file, not a '{}' one", k, kind));
  const auto v = r.pod<std::uint32_t>();
  if (v != version)
    r.fail(fmt::format("has format version {}, this needlesim reads version {} (written by another version)", v, version));
  const auto len = r.pod<std::uint64_t>();
  const std::size_t headLen = kMagic.size() + sizeof(std::uint64_t) + k.size() + sizeof(std::uint32_t) + sizeof(std::uint64_t);
  if (bytes.size() < headLen + sizeof(std::uint64_t) || len != bytes.size() - headLen - sizeof(std::uint64_t))
    r.fail(fmt::format("truncated or padded: {} bytes, the header announces {}", bytes.size(),
                       headLen + len + sizeof(std::uint64_t)));
  std::uint64_t sum;
  std::memcpy(&sum, bytes.data() + bytes.size() - sizeof sum, sizeof sum);
  if (sum != fnv1a64(std::string_view(bytes).substr(0, bytes.size() - sizeof sum)))
    r.fail("is corrupt (checksum mismatch)");
  return BinaryReader(bytes.substr(headLen, static_cast<std::size_t>(len)), name);
}

}  // namespace needlesim::io
