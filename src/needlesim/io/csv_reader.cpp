#include "needlesim/io/csv_reader.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <cmath>
#include <fstream>
#include <optional>
#include <sstream>
#include <stdexcept>

#include "needlesim/core/error.hpp"

namespace needlesim::io {

namespace {

const char* const kHeaderHelp =
    "a header naming each column with its unit, 'name [unit]', 'name (unit)' or 'name_unit', "
    "separated by ',', ';' or tabs, e.g. 'strain [1], stress [kPa]'";
const char* const kNumberHelp = "a finite decimal number such as 0.25 or -1.5e3";
// Fits sum squares of values: beyond this magnitude (SI) they overflow.
constexpr double kLargestValue = 1e100;

std::string_view trim(std::string_view s) {
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.remove_suffix(1);
  return s;
}

std::string lower(std::string_view s) {
  std::string r(s);
  for (auto& c : r) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return r;
}

// The name columns are compared by: lower case, '_' read as a space, runs of spaces as one.
std::string normalName(std::string_view s) {
  std::string r;
  for (char c : lower(trim(s))) {
    const bool space = c == '_' || std::isspace(static_cast<unsigned char>(c));
    if (!space) r += c;
    else if (!r.empty() && r.back() != ' ') r += ' ';
  }
  if (!r.empty() && r.back() == ' ') r.pop_back();
  return r;
}

std::string separatorName(char sep) { return sep == '\t' ? "a tab" : std::string("'") + sep + "'"; }

// Skips a UTF-8 byte-order mark (Excel's "CSV UTF-8"); refuses UTF-16 and UTF-32 text.
std::string_view skipByteOrderMark(std::string_view text, const std::string& file) {
  constexpr std::string_view utf8 = "\xEF\xBB\xBF";
  if (text.substr(0, utf8.size()) == utf8) return text.substr(utf8.size());
  const bool utf16 = text.size() >= 2 && ((text[0] == '\xFF' && text[1] == '\xFE') ||
                                          (text[0] == '\xFE' && text[1] == '\xFF'));
  const bool utf32be = text.size() >= 4 && text.substr(0, 4) == std::string_view("\0\0\xFE\xFF", 4);
  if (utf16 || utf32be)
    throw InputError({file, 1, 1}, "encoding", "", "the file is UTF-16 or UTF-32 text",
                     "UTF-8 or ASCII text: save it as 'CSV UTF-8' or plain CSV");
  return text;
}

// One source line; `rest` is advanced past its end ("\n", "\r\n" or a lone "\r").
std::string_view nextLine(std::string_view& rest) {
  const std::size_t eol = rest.find_first_of("\r\n");
  if (eol == std::string_view::npos) {
    std::string_view line = rest;
    rest = {};
    return line;
  }
  std::string_view line = rest.substr(0, eol);
  const std::size_t skip = (rest[eol] == '\r' && eol + 1 < rest.size() && rest[eol + 1] == '\n') ? 2 : 1;
  rest.remove_prefix(eol + skip);
  return line;
}

struct Field {
  std::string text;  // trimmed, quotes removed
  int column = 0;    // 1-based position of the field in the line
};

bool isBlank(char c, char sep) { return c != sep && (c == ' ' || c == '\t'); }

// The text of a quoted field starting at line[pos] == '"'; pos ends after the closing quote.
std::string readQuoted(std::string_view line, std::size_t& pos, const std::string& file, int lineNo) {
  const std::size_t open = pos++;
  std::string text;
  while (pos < line.size()) {
    if (line[pos] != '"') {
      text += line[pos++];
    } else if (pos + 1 < line.size() && line[pos + 1] == '"') {
      text += '"';
      pos += 2;
    } else {
      ++pos;
      return text;
    }
  }
  throw InputError({file, lineNo, static_cast<int>(open) + 1}, "field", std::string(line.substr(open)),
                   "the quote is not closed on this line",
                   "a field in double quotes closed on the same line, with \"\" for a quote inside it");
}

// Splits a line at sep outside double quotes.
std::vector<Field> splitFields(std::string_view line, char sep, const std::string& file, int lineNo) {
  std::vector<Field> out;
  std::size_t pos = 0;
  while (true) {
    Field f;
    f.column = static_cast<int>(pos) + 1;
    while (pos < line.size() && isBlank(line[pos], sep)) ++pos;
    if (pos < line.size() && line[pos] == '"') {
      f.text = std::string(trim(readQuoted(line, pos, file, lineNo)));
      while (pos < line.size() && isBlank(line[pos], sep)) ++pos;
      if (pos < line.size() && line[pos] != sep)
        throw InputError({file, lineNo, static_cast<int>(pos) + 1}, "field", std::string(line.substr(f.column - 1)),
                         "text after the closing quote",
                         "the separator " + separatorName(sep) + " right after a quoted field");
    } else {
      const std::size_t end = std::min(line.find(sep, pos), line.size());
      f.text = std::string(trim(line.substr(pos, end - pos)));
      pos = end;
    }
    out.push_back(std::move(f));
    if (pos >= line.size()) return out;
    ++pos;  // the separator
  }
}

// The column separator: the one of ',', ';' and tab that the header line uses outside quotes.
char sniffSeparator(std::string_view header, const std::string& file, int lineNo) {
  constexpr std::array<char, 3> kSeparators{',', ';', '\t'};
  std::array<int, 3> count{};
  bool quoted = false;
  for (char c : header) {
    if (c == '"') quoted = !quoted;
    for (std::size_t k = 0; k < kSeparators.size(); ++k)
      if (!quoted && c == kSeparators[k]) ++count[k];
  }
  char sep = ',';
  std::string used;
  for (std::size_t k = 0; k < kSeparators.size(); ++k) {
    if (count[k] == 0) continue;
    if (!used.empty()) {
      used += ", ";
      sep = 0;
    } else {
      sep = kSeparators[k];
    }
    used += std::to_string(count[k]) + " x " + separatorName(kSeparators[k]);
  }
  if (sep == 0)
    throw InputError({file, lineNo, 0}, "header", std::string(header),
                     "the header line mixes column separators (" + used + "), so the separator is ambiguous",
                     "one separator between all columns: ',', ';' or a tab; put a column name that "
                     "contains another one in double quotes");
  return sep;
}

struct UnitScale {
  units::Dim dim;
  double scale = 1.0;
};

// Spellings lab software uses for units needlesim writes otherwise.
std::string_view canonicalUnit(std::string_view unit) {
  const std::string u = lower(unit);
  if (u == "pct" || u == "percent") return "%";
  if (u == "sec") return "s";
  return unit;
}

// SI dimension and scale of a unit written in a header; throws std::logic_error
// (std::invalid_argument, or std::out_of_range for an exponent) with the reason.
UnitScale resolveUnit(std::string_view unit) {
  if (unit.empty() || unit == "1" || unit == "-") return {};
  std::string text = "1 ";
  text += canonicalUnit(unit);
  const units::Quantity q = units::parse(text);
  if (q.gauge) throw std::invalid_argument("a needle gauge is not a unit for data");
  return {q.dim, q.value};
}

bool resolvesAsUnit(std::string_view unit) {
  if (unit.empty() || !(std::isalpha(static_cast<unsigned char>(unit.front())) || unit.front() == '%')) return false;
  try {
    resolveUnit(unit);
    return true;
  } catch (const std::logic_error&) {
    return false;
  }
}

struct NameAndUnit {
  std::string_view name, unit;
};

// The unit written after the name: "name [unit]", "name (unit)" (the last parentheses) or "name_unit".
NameAndUnit splitNameAndUnit(std::string_view f, const std::string& file, int lineNo, int col) {
  const auto bad = [&](const std::string& problem) {
    return InputError({file, lineNo, col}, "column '" + normalName(f) + "'", std::string(f), problem, kHeaderHelp);
  };
  for (auto [open, close] : {std::pair{'[', ']'}, std::pair{'(', ')'}}) {
    const std::size_t lb = open == '[' ? f.find(open) : f.rfind(open);
    if (lb == std::string_view::npos) continue;
    const std::size_t rb = f.find(close, lb);
    if (rb == std::string_view::npos) throw bad(std::string("the unit has no closing '") + close + "'");
    if (!trim(f.substr(rb + 1)).empty()) throw bad("text after the unit");
    return {trim(f.substr(0, lb)), trim(f.substr(lb + 1, rb - lb - 1))};
  }
  const std::size_t us = f.rfind('_');
  if (us != std::string_view::npos && us > 0 && resolvesAsUnit(f.substr(us + 1)))
    return {trim(f.substr(0, us)), f.substr(us + 1)};
  return {f, {}};
}

CsvColumn readColumn(const Field& f, const std::string& file, int lineNo) {
  const NameAndUnit nu = splitNameAndUnit(f.text, file, lineNo, f.column);
  CsvColumn c;
  c.headerColumn = f.column;
  c.name = normalName(nu.name);
  if (c.name.empty())
    throw InputError({file, lineNo, f.column}, "header", f.text,
                     "a column has no name (an empty field, or a separator at the end of the line)", kHeaderHelp);
  c.unit = std::string(nu.unit);
  try {
    const UnitScale u = resolveUnit(nu.unit);
    c.dim = u.dim;
    c.scale = u.scale;
  } catch (const std::logic_error& e) {
    throw InputError({file, lineNo, f.column}, "column '" + c.name + "'", c.unit, std::string("unknown unit: ") + e.what(),
                     "SI units with prefixes, e.g. Pa, kPa, N, mm, s, mm/s, %, 1");
  }
  return c;
}

std::vector<CsvColumn> readHeader(const std::vector<Field>& fields, const std::string& file, int lineNo) {
  std::vector<CsvColumn> columns;
  for (const Field& f : fields) {
    CsvColumn c = readColumn(f, file, lineNo);
    const bool unitFromSuffix = !c.unit.empty() && f.text.find_first_of("[(") == std::string::npos;
    for (const auto& other : columns)
      if (other.name == c.name)
        throw InputError({file, lineNo, f.column}, "header", f.text,
                         "the column name '" + c.name + "' appears twice" +
                             (unitFromSuffix ? " ('_" + c.unit + "' is read as the unit)" : std::string()),
                         "each column named once; a name ending in '_word' that is not a unit keeps it when "
                         "the unit is in brackets, e.g. 'force_min [N]'");
    columns.push_back(std::move(c));
  }
  return columns;
}

// Reads the numbers of one file, holding it to one decimal mark.
class NumberReader {
 public:
  NumberReader(std::string file, char separator) : file_(std::move(file)), separator_(separator) {}

  double read(const Field& f, const std::string& column, int lineNo) {
    const std::string field = "column '" + column + "'";
    const auto bad = [&](const std::string& problem, const std::string& allowed) {
      return InputError({file_, lineNo, f.column}, field, f.text, problem, allowed);
    };
    if (f.text.empty()) throw bad("the value is missing", kNumberHelp);
    const auto commas = std::count(f.text.begin(), f.text.end(), ',');
    const auto points = std::count(f.text.begin(), f.text.end(), '.');
    if (commas > 0 && separator_ == ',')
      throw bad("a decimal comma in a comma-separated file is ambiguous",
                "a decimal point (0.25), or columns separated by ';' or tabs when the numbers use decimal commas");
    if (commas + points > 1)
      throw bad("the number has more than one decimal mark (a thousands separator?)",
                "numbers without thousands separators, e.g. 1234.5 or 1234,5");
    if (commas + points == 1) holdToOneMark(commas ? ',' : '.', f, column, lineNo);
    std::string text = f.text;
    std::replace(text.begin(), text.end(), ',', '.');
    return parseNumber(text, bad);
  }

  char decimalMark() const { return first_.mark == ',' ? ',' : '.'; }

 private:
  struct FirstMark {
    char mark = 0;
    int line = 0;
    std::string column, value;
  };

  static std::string markName(char m) { return m == ',' ? "a decimal comma" : "a decimal point"; }

  void holdToOneMark(char mark, const Field& f, const std::string& column, int lineNo) {
    if (first_.mark == 0) {
      first_ = {mark, lineNo, column, f.text};
      return;
    }
    if (mark == first_.mark) return;
    throw InputError({file_, lineNo, f.column}, "column '" + column + "'", f.text,
                     "the value has " + markName(mark) + " but line " + std::to_string(first_.line) + " (column '" +
                         first_.column + "', '" + first_.value + "') has " + markName(first_.mark) +
                         "; with decimal commas a '.' may be a thousands separator",
                     "one decimal mark in the whole file: ',' (1,5) in files separated by ';' or tabs, or '.' (1.5)");
  }

  template <class Bad>
  static double parseNumber(const std::string& text, const Bad& bad) {
    double v = 0;
    const char* b = text.data();
    const char* e = text.data() + text.size();
    if (b != e && *b == '+') ++b;
    auto [ptr, ec] = std::from_chars(b, e, v);
    if (ec != std::errc() || ptr != e) {
      const std::string lt = lower(text);
      const bool nan = lt == "nan" || lt == "-nan" || lt == "inf" || lt == "-inf" || lt == "infinity";
      throw bad(nan ? "the value is not a finite number" : "the value is not a number", kNumberHelp);
    }
    if (!std::isfinite(v)) throw bad("the value is not a finite number", kNumberHelp);
    return v;
  }

  std::string file_;
  char separator_;
  FirstMark first_;
};

// The value in SI; refuses one too large to compute with (also after the unit's scale).
double toSI(double value, const CsvColumn& c, const Field& f, const std::string& file, int lineNo) {
  const double si = value * c.scale;
  if (!(std::abs(si) <= kLargestValue))
    throw InputError({file, lineNo, f.column}, "column '" + c.name + "'", f.text + (c.unit.empty() ? "" : " " + c.unit),
                     "the value is too large to compute with",
                     "magnitudes up to 1e100 in SI units (Pa, m, N, s)");
  return si;
}

}  // namespace

int CsvData::find(const std::vector<std::string>& names) const {
  for (const auto& n : names) {
    const std::string want = normalName(n);
    for (std::size_t c = 0; c < columns.size(); ++c)
      if (columns[c].name == want) return static_cast<int>(c);
  }
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

std::string CsvData::formatNote() const {
  if (separator == ',' && decimalMark == '.') return "";
  std::string note = "read as columns separated by " + separatorName(separator);
  if (decimalMark == ',') note += ", numbers with decimal commas";
  return note;
}

CsvData parseCsv(std::string_view text, const std::string& fileName) {
  CsvData d;
  d.file = fileName;
  std::string_view rest = skipByteOrderMark(text, fileName);
  std::optional<NumberReader> numbers;
  for (int lineNo = 1; !rest.empty(); ++lineNo) {
    const std::string_view line = nextLine(rest);
    const std::string_view t = trim(line);
    if (t.empty() || t.front() == '#') continue;
    if (!numbers) {
      d.headerLine = lineNo;
      d.separator = sniffSeparator(line, fileName, lineNo);
      d.columns = readHeader(splitFields(line, d.separator, fileName, lineNo), fileName, lineNo);
      d.values.assign(d.columns.size(), {});
      numbers.emplace(fileName, d.separator);
      continue;
    }
    const std::vector<Field> fields = splitFields(line, d.separator, fileName, lineNo);
    if (fields.size() != d.columns.size())
      throw InputError({fileName, lineNo, 0}, "row", std::string(t),
                       "the row has " + std::to_string(fields.size()) + " fields but the header (line " +
                           std::to_string(d.headerLine) + ") names " + std::to_string(d.columns.size()),
                       "one number per column, separated by " + separatorName(d.separator) +
                           (d.separator == ',' && fields.size() > d.columns.size()
                                ? "; numbers with decimal commas need columns separated by ';' or tabs"
                                : ""));
    for (std::size_t c = 0; c < fields.size(); ++c)
      d.values[c].push_back(toSI(numbers->read(fields[c], d.columns[c].name, lineNo), d.columns[c], fields[c], fileName, lineNo));
    d.lines.push_back(lineNo);
  }
  if (!numbers)
    throw InputError({fileName, 1, 0}, "header", "", "the file is empty (no header, no data)", kHeaderHelp);
  if (d.rows() == 0)
    throw InputError({fileName, d.headerLine, 0}, "data", "", "the file has a header but no data rows",
                     "one row of numbers per measurement below the header");
  d.decimalMark = numbers->decimalMark();
  return d;
}

CsvData readCsv(const std::filesystem::path& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec))
    throw InputError({path.string(), 0, 0}, "data file", path.string(), "is a folder, not a file",
                     "an existing, readable CSV file");
  std::ifstream in(path, std::ios::binary);
  if (!in)
    throw InputError({path.string(), 0, 0}, "data file", path.string(), "cannot be opened",
                     "an existing, readable CSV file");
  std::ostringstream ss;
  ss << in.rdbuf();
  return parseCsv(ss.str(), path.string());
}

}  // namespace needlesim::io
