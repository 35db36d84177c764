#include "needlesim/io/csv_reader.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "needlesim/core/error.hpp"

namespace needlesim::io {

namespace {

std::string_view trim(std::string_view s) {
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.remove_suffix(1);
  return s;
}

std::vector<std::pair<std::string_view, int>> splitFields(std::string_view line) {
  std::vector<std::pair<std::string_view, int>> out;
  std::size_t start = 0;
  for (std::size_t i = 0; i <= line.size(); ++i) {
    if (i == line.size() || line[i] == ',') {
      out.emplace_back(trim(line.substr(start, i - start)), static_cast<int>(start) + 1);
      start = i + 1;
    }
  }
  return out;
}

std::string lower(std::string_view s) {
  std::string r(s);
  for (auto& c : r) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return r;
}

const char* kHeaderHelp =
    "a header of comma-separated 'name [unit]' columns, e.g. 'strain [1], stress [kPa]'";

}  // namespace

int CsvData::find(const std::vector<std::string>& names) const {
  for (const auto& n : names)
    for (std::size_t c = 0; c < columns.size(); ++c)
      if (columns[c].name == n) return static_cast<int>(c);
  return -1;
}

void CsvData::checkDim(int c, units::Dim dim, const std::string& what) const {
  const auto& col = columns.at(static_cast<std::size_t>(c));
  if (col.dim == dim) return;
  throw InputError({file, headerLine, col.headerColumn}, "column '" + col.name + "'",
                   col.unit.empty() ? "(no unit)" : col.unit,
                   "the unit of " + what + " has the wrong dimension",
                   dim == units::dim::None ? std::string("a dimensionless unit: [1], [-] or [%]")
                                           : units::examples(dim));
}

int CsvData::require(const std::vector<std::string>& names, units::Dim dim, const std::string& what) const {
  int c = find(names);
  if (c < 0) {
    std::string allowed;
    for (const auto& n : names) allowed += (allowed.empty() ? "'" : ", '") + n + "'";
    std::string have;
    for (const auto& col : columns) have += (have.empty() ? "" : ", ") + col.name;
    throw InputError({file, headerLine, 0}, "header", have, "no column for " + what,
                     "a column named " + allowed + " with a unit, e.g. '" + names.front() + " [" +
                         (dim == units::dim::None ? std::string("1") : units::siName(dim)) + "]'");
  }
  checkDim(c, dim, what);
  return c;
}

CsvData parseCsv(std::string_view text, const std::string& fileName) {
  CsvData d;
  d.file = fileName;
  int lineNo = 0;
  std::size_t pos = 0;
  bool haveHeader = false;
  while (pos <= text.size()) {
    std::size_t eol = text.find('\n', pos);
    if (eol == std::string_view::npos) eol = text.size();
    std::string_view line = text.substr(pos, eol - pos);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    pos = eol + 1;
    ++lineNo;
    std::string_view t = trim(line);
    if (t.empty() || t.front() == '#') {
      if (eol == text.size()) break;
      continue;
    }
    auto fields = splitFields(line);
    if (!haveHeader) {
      haveHeader = true;
      d.headerLine = lineNo;
      if (fields.size() == 1 && (t.find(';') != std::string_view::npos || t.find('\t') != std::string_view::npos))
        throw InputError({fileName, lineNo, 0}, "header", std::string(t),
                         "columns are separated by ';' or tabs", "commas between columns, e.g. 'strain [1], stress [kPa]'");
      for (auto [f, col] : fields) {
        CsvColumn c;
        c.headerColumn = col;
        std::size_t lb = f.find('[');
        std::string_view name = trim(f.substr(0, lb));
        if (name.empty())
          throw InputError({fileName, lineNo, col}, "header", std::string(f), "a column has no name",
                           kHeaderHelp);
        c.name = lower(name);
        if (lb != std::string_view::npos) {
          std::size_t rb = f.find(']', lb);
          if (rb == std::string_view::npos)
            throw InputError({fileName, lineNo, col}, "column '" + c.name + "'", std::string(f),
                             "the unit has no closing ']'", kHeaderHelp);
          c.unit = std::string(trim(f.substr(lb + 1, rb - lb - 1)));
          if (!trim(f.substr(rb + 1)).empty())
            throw InputError({fileName, lineNo, col}, "column '" + c.name + "'", std::string(f),
                             "text after the unit", kHeaderHelp);
        }
        if (!c.unit.empty() && c.unit != "1" && c.unit != "-") {
          try {
            units::Quantity q = units::parse("1 " + c.unit);
            if (q.gauge) throw std::invalid_argument("gauge is not a unit for data");
            c.dim = q.dim;
            c.scale = q.value;
          } catch (const std::invalid_argument& e) {
            throw InputError({fileName, lineNo, col}, "column '" + c.name + "'", c.unit,
                             std::string("unknown unit: ") + e.what(),
                             "SI units with prefixes, e.g. Pa, kPa, N, mm, s, mm/s, %, 1");
          }
        }
        for (const auto& other : d.columns)
          if (other.name == c.name)
            throw InputError({fileName, lineNo, col}, "header", c.name, "the column name appears twice",
                             "each column named once");
        d.columns.push_back(c);
      }
      d.values.assign(d.columns.size(), {});
      if (eol == text.size()) break;
      continue;
    }
    if (fields.size() != d.columns.size())
      throw InputError({fileName, lineNo, 0}, "row", std::string(t),
                       "the row has " + std::to_string(fields.size()) + " fields but the header (line " +
                           std::to_string(d.headerLine) + ") names " + std::to_string(d.columns.size()),
                       "one number per column, separated by commas");
    for (std::size_t c = 0; c < fields.size(); ++c) {
      auto [f, col] = fields[c];
      std::string field = "column '" + d.columns[c].name + "'";
      double v = 0;
      const char* b = f.data();
      const char* e = f.data() + f.size();
      if (b != e && *b == '+') ++b;
      auto [ptr, ec] = std::from_chars(b, e, v);
      if (f.empty() || ec != std::errc() || ptr != e) {
        std::string lf = lower(f);
        bool nan = lf == "nan" || lf == "-nan" || lf == "inf" || lf == "-inf" || lf == "infinity";
        throw InputError({fileName, lineNo, col}, field, std::string(f),
                         f.empty() ? "the value is missing"
                                   : (nan ? "the value is not a finite number" : "the value is not a number"),
                         "a finite decimal number such as 0.25 or -1.5e3");
      }
      if (!std::isfinite(v))
        throw InputError({fileName, lineNo, col}, field, std::string(f), "the value is not a finite number",
                         "a finite decimal number such as 0.25 or -1.5e3");
      d.values[c].push_back(v * d.columns[c].scale);
    }
    d.lines.push_back(lineNo);
    if (eol == text.size()) break;
  }
  if (!haveHeader)
    throw InputError({fileName, 1, 0}, "header", "", "the file is empty (no header, no data)", kHeaderHelp);
  if (d.rows() == 0)
    throw InputError({fileName, d.headerLine, 0}, "data", "", "the file has a header but no data rows",
                     "one row of numbers per measurement below the header");
  return d;
}

CsvData readCsv(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in)
    throw InputError({path.string(), 0, 0}, "data file", path.string(), "cannot be opened",
                     "an existing, readable CSV file");
  std::ostringstream ss;
  ss << in.rdbuf();
  return parseCsv(ss.str(), path.string());
}

}  // namespace needlesim::io
