#pragma once
// Versioned binary state files (checkpoints of long runs, results/checkpoint.hpp).
// A file is: the magic "NSSTATE\n", the kind (e.g. "checkpoint"), the format
// version, the payload length, the payload, and an FNV-1a 64-bit checksum of
// everything before it. Readers check all of these and name the file and
// what is wrong (truncated, another kind, another version, corrupt), so a
// stale or damaged file is an input error, never a crash. Inside the payload
// the writer puts named tags between sections, so a layout change is found
// at the section where it happens. Values are stored in the machine's byte
// order (little-endian on every supported platform; checked by the magic).
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "needlesim/io/table.hpp"

namespace needlesim::io {

std::uint64_t fnv1a64(std::string_view bytes, std::uint64_t h = 0xcbf29ce484222325ull);

class BinaryWriter {
 public:
  template <class T>
  void pod(const T& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    buf_.append(reinterpret_cast<const char*>(&v), sizeof(T));
  }
  template <class T>
  void vec(const std::vector<T>& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    pod(static_cast<std::uint64_t>(v.size()));
    buf_.append(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T));
  }
  void str(std::string_view s) {
    pod(static_cast<std::uint64_t>(s.size()));
    buf_.append(s.data(), s.size());
  }
  void tag(std::string_view name) { str(name); }  // checked by BinaryReader::tag
  void table(const Table& t);
  const std::string& bytes() const { return buf_; }

 private:
  std::string buf_;
};

class BinaryReader {
 public:
  // origin: the file the bytes came from (named in every error).
  BinaryReader(std::string bytes, std::string origin) : buf_(std::move(bytes)), origin_(std::move(origin)) {}
  template <class T>
  void pod(T& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    need(sizeof(T));
    std::memcpy(&v, buf_.data() + pos_, sizeof(T));
    pos_ += sizeof(T);
  }
  template <class T>
  T pod() {
    T v;
    pod(v);
    return v;
  }
  // A vector; `expected` (if not npos) is the length the reader requires.
  template <class T>
  std::vector<T> vec(std::size_t expected = npos, std::string_view what = {}) {
    static_assert(std::is_trivially_copyable_v<T>);
    const auto n = pod<std::uint64_t>();
    if (expected != npos && n != expected) mismatch(what, n, expected);
    if (n > (buf_.size() - pos_) / (sizeof(T) > 0 ? sizeof(T) : 1)) fail("truncated (an array runs past the end of the file)");
    std::vector<T> v(static_cast<std::size_t>(n));
    std::memcpy(v.data(), buf_.data() + pos_, v.size() * sizeof(T));
    pos_ += v.size() * sizeof(T);
    return v;
  }
  std::string str();
  // The next section must be `name`.
  void tag(std::string_view name);
  Table table();
  bool atEnd() const { return pos_ == buf_.size(); }
  const std::string& origin() const { return origin_; }
  // Throws an InputError naming the file: "<file>: <problem>".
  [[noreturn]] void fail(const std::string& problem) const;
  [[noreturn]] void mismatch(std::string_view what, std::uint64_t got, std::uint64_t want) const;
  static constexpr std::size_t npos = static_cast<std::size_t>(-1);

 private:
  void need(std::size_t n) const {
    if (n > buf_.size() - pos_) fail("truncated (ends inside a record)");
  }
  std::string buf_;
  std::string origin_;
  std::size_t pos_ = 0;
};

// The first bytes of every state file.
inline constexpr std::string_view kStateFileMagic = "NSSTATE\n";

// The framed bytes of a state file (see the file comment).
std::string frameState(std::string_view kind, std::uint32_t version, std::string_view payload);
// Reads and checks a state file; returns a reader over its payload. Throws
// InputError naming the file when it is missing, truncated, corrupt, of
// another kind or of another format version.
BinaryReader readStateFile(const std::filesystem::path& file, std::string_view kind, std::uint32_t version);

}  // namespace needlesim::io
