#pragma once
// Reads numeric CSV data whose header names each column with its unit and
// converts the values to SI. It reads what lab software writes:
//  - a UTF-8 byte-order mark (Excel's "CSV UTF-8") is skipped;
//  - the separator (',', ';' or a tab) is taken from the header line;
//  - fields may be quoted ("Stress (kPa)"), with "" for a quote inside;
//  - the unit follows the name in brackets, in parentheses or after the last
//    '_': "stress [kPa]", "Stress (kPa)", "stress_kPa"; "pct" and "percent"
//    mean %;
//  - in files separated by ';' or tabs, numbers may use a decimal comma
//    ("1,5"); one decimal mark per file.
// Column names are compared in lower case with '_' read as a space. Lines
// starting with '#' and blank lines are skipped. Every problem is an
// InputError naming file, line, column and value.
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "needlesim/core/units.hpp"

namespace needlesim::io {

struct CsvColumn {
  std::string name;  // lower case, trimmed
  std::string unit;  // as written ("" for none)
  units::Dim dim;
  double scale = 1.0;  // SI value of one unit
  int headerColumn = 0;
};

struct CsvData {
  std::string file;  // for messages
  int headerLine = 0;
  char separator = ',';     // ',', ';' or '\t'
  char decimalMark = '.';   // '.' or ','
  std::vector<CsvColumn> columns;
  std::vector<std::vector<double>> values;  // values[column][row], SI
  std::vector<int> lines;                   // source line of each row

  std::size_t rows() const { return lines.size(); }
  // Index of the first column whose name is one of names ('_' and ' ' alike); -1 if none.
  int find(const std::vector<std::string>& names) const;
  // Like find, but throws an InputError (naming the header line and what is
  // allowed) when absent or when the column's unit has another dimension.
  int require(const std::vector<std::string>& names, units::Dim dim, const std::string& what) const;
  // Checks the dimension of an existing column; throws InputError otherwise.
  void checkDim(int column, units::Dim dim, const std::string& what) const;
  const std::vector<double>& col(int c) const { return values.at(static_cast<std::size_t>(c)); }
  // How the file was read when it is not plain comma-separated CSV with decimal
  // points, e.g. "separated by ';', decimal commas"; "" otherwise.
  std::string formatNote() const;
};

CsvData parseCsv(std::string_view text, const std::string& fileName);
CsvData readCsv(const std::filesystem::path& path);  // throws InputError if unreadable

}  // namespace needlesim::io
