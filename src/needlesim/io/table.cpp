#include "needlesim/io/table.hpp"

#include <fmt/format.h>

#include "needlesim/core/error.hpp"

namespace needlesim::io {

void Table::addRow(std::initializer_list<double> row) {
  if (row.size() != columns_.size()) throw Error("internal: table row has the wrong number of columns");
  data_.insert(data_.end(), row.begin(), row.end());
}

void Table::addRow(const std::vector<double>& row) {
  if (row.size() != columns_.size()) throw Error("internal: table row has the wrong number of columns");
  data_.insert(data_.end(), row.begin(), row.end());
}

std::size_t Table::columnIndex(const std::string& name) const {
  for (std::size_t i = 0; i < columns_.size(); ++i)
    if (columns_[i].name == name) return i;
  throw Error("internal: table has no column " + name);
}

std::vector<double> Table::column(const std::string& name) const {
  std::size_t c = columnIndex(name);
  std::vector<double> out(rows());
  for (std::size_t r = 0; r < out.size(); ++r) out[r] = at(r, c);
  return out;
}

std::string Table::csv() const {
  std::string s;
  s.reserve(rows() * columns_.size() * 14 + 256);
  for (std::size_t c = 0; c < columns_.size(); ++c)
    s += fmt::format("{}{} [{}]", c ? "," : "", columns_[c].name, columns_[c].unit);
  s += '\n';
  auto out = std::back_inserter(s);
  for (std::size_t r = 0; r < rows(); ++r) {
    for (std::size_t c = 0; c < columns_.size(); ++c) {
      if (exact_)
        fmt::format_to(out, "{}{}", c ? "," : "", at(r, c));
      else
        fmt::format_to(out, "{}{:.10g}", c ? "," : "", at(r, c));
    }
    s += '\n';
  }
  return s;
}

}  // namespace needlesim::io
