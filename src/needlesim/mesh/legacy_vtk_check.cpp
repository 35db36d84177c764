// Pre-check of legacy VTK surfaces before Gmsh reads them: header, points, cell-section counts.
#include "needlesim/mesh/legacy_vtk_check.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <sstream>
#include <vector>

#include "needlesim/mesh/surface_checks.hpp"

namespace needlesim::mesh {

namespace {

const char* kAllowed =
    "a legacy VTK file (version 4.2 or older): '# vtk DataFile Version', a title, ASCII or BINARY, DATASET POLYDATA "
    "or UNSTRUCTURED_GRID, POINTS n float|double with 3 n finite values, then cell sections whose counts match their data";

class LegacyVtk {
 public:
  LegacyVtk(const std::string& path, const std::string& bytes) : path_(path), b_(bytes) {}

  void check() {
    const std::string first = line();
    if (!first.starts_with("# vtk DataFile")) throw error(1, "does not start with '# vtk DataFile Version'");
    line();  // the title
    const std::string mode = trimmed(line());
    if (mode != "ASCII" && mode != "BINARY") throw error(3, fmt::format("has \"{}\" where ASCII or BINARY is expected", printable(mode)));
    binary_ = mode == "BINARY";
    while (nextWords()) {
      const std::string& key = words_[0];
      if (key == "DATASET") continue;
      if (key == "POINTS") points();
      else if (key == "POLYGONS" || key == "CELLS" || key == "LINES" || key == "VERTICES" || key == "TRIANGLE_STRIPS") cells();
      else if (key == "CELL_TYPES") integers(count(1, "cell types", binary_ ? 4 : 2), "cell types");
      else return;  // point or cell data: not read as geometry
    }
  }

 private:
  InputError error(int line, const std::string& problem) const { return surfaceError(path_, line, problem, kAllowed); }
  std::string line() {
    ++lineNo_;
    const std::size_t end = std::min(b_.find('\n', at_), b_.size());
    std::string s = b_.substr(std::min(at_, b_.size()), end - std::min(at_, b_.size()));
    at_ = end + 1;
    return s;
  }
  static std::string trimmed(std::string s) {
    s.erase(s.find_last_not_of(" \t\r") + 1);
    s.erase(0, s.find_first_not_of(" \t"));
    return s;
  }
  bool nextWords() {
    while (at_ < b_.size()) {
      std::istringstream in(line());
      words_.clear();
      for (std::string w; in >> w;) words_.push_back(w);
      if (!words_.empty()) return true;
    }
    return false;
  }
  std::size_t left() const { return b_.size() - std::min(at_, b_.size()); }
  // Word k of the keyword line as a count of things taking at least `least` bytes each.
  std::uint64_t count(std::size_t k, const std::string& what, double least) const {
    const std::string w = k < words_.size() ? words_[k] : "";
    if (w.empty() || w.size() > 15 || w.find_first_not_of("0123456789") != std::string::npos)
      throw error(lineNo_, fmt::format("{} has \"{}\" where the number of {} is expected", words_[0], printable(w), what));
    const std::uint64_t n = std::strtoull(w.c_str(), nullptr, 10);
    if (static_cast<double>(n) * least > static_cast<double>(left()))
      throw error(lineNo_, fmt::format("{} declares {} {}, more than the {} bytes that follow can hold", words_[0], n, what, left()));
    return n;
  }
  void points() {
    const std::string type = words_.size() == 3 ? words_[2] : "";
    if (type != "float" && type != "double")
      throw error(lineNo_, fmt::format("has POINTS of type \"{}\"", printable(type)) + " (float or double expected)");
    const int size = type == "float" ? 4 : 8;
    const std::uint64_t n = count(1, "points", binary_ ? 3.0 * size : 6.0);
    const int line = lineNo_;
    for (std::uint64_t i = 0; i < n; ++i) {
      double p[3];
      for (double& x : p) x = binary_ ? binaryReal(size, n, i) : textReal(n, i);
      checkVertex(path_, binary_ ? line : lineNo_ + 1, [&] { return fmt::format("point {} (numbered from 0)", i); }, p, kAllowed);
    }
  }
  double binaryReal(int size, std::uint64_t n, std::uint64_t i) {
    if (left() < static_cast<std::size_t>(size)) throw error(lineNo_, fmt::format("declares {} points; the data ends at point {}", n, i));
    unsigned char b[8];
    std::memcpy(b, b_.data() + at_, static_cast<std::size_t>(size));
    std::reverse(b, b + size);  // legacy VTK binary data is big-endian
    at_ += static_cast<std::size_t>(size);
    if (size == 4) {
      float f;
      std::memcpy(&f, b, 4);
      return f;
    }
    double d;
    std::memcpy(&d, b, 8);
    return d;
  }
  // The next whitespace-separated word of ASCII data (lineNo_ kept), "" at the end.
  std::string textWord() {
    while (at_ < b_.size() && std::isspace(static_cast<unsigned char>(b_[at_]))) lineNo_ += b_[at_++] == '\n';
    const std::size_t from = at_;
    while (at_ < b_.size() && !std::isspace(static_cast<unsigned char>(b_[at_]))) ++at_;
    return b_.substr(from, at_ - from);
  }
  double textReal(std::uint64_t n, std::uint64_t i) {
    const std::string w = textWord();
    if (w.empty()) throw error(lineNo_, fmt::format("declares {} points; the data ends at point {}", n, i));
    char* end = nullptr;
    const double v = std::strtod(w.c_str(), &end);
    if (*end != '\0') throw error(lineNo_ + 1, fmt::format("point {} has \"{}\", not a number", i, printable(w)));
    return v;
  }
  void cells() {
    count(1, "cells", binary_ ? 4 : 2);
    integers(count(2, "cell values", binary_ ? 4 : 2), "cell values");
  }
  void integers(std::uint64_t n, const std::string& what) {
    if (binary_) {
      at_ += 4 * static_cast<std::size_t>(n);  // bounded by count()
      return;
    }
    for (std::uint64_t i = 0; i < n; ++i) {
      const std::string w = textWord();
      if (w.empty() || w.size() > 12 || w.find_first_not_of("-0123456789") != std::string::npos)
        throw error(lineNo_ + 1, fmt::format("{} declares {} {}; value {} is \"{}\"", words_[0], n, what, i + 1, printable(w)));
    }
  }

  std::string path_;
  const std::string& b_;
  std::size_t at_ = 0;
  int lineNo_ = 0;
  bool binary_ = false;
  std::vector<std::string> words_;
};

}  // namespace

void checkLegacyVtk(const std::string& path) {
  const std::string bytes = readSurfaceBytes(path, kAllowed);
  LegacyVtk(path, bytes).check();
}

}  // namespace needlesim::mesh
