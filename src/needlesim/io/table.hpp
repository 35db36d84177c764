#pragma once
// A numeric table with named, unit-labelled columns: the form in which every
// engine reports time series. Written as CSV with a header "name [unit]".
#include <string>
#include <vector>

namespace needlesim::io {

struct Column {
  std::string name;
  std::string unit;  // SI unit text, "1" for dimensionless
};

class Table {
 public:
  Table() = default;
  explicit Table(std::vector<Column> columns) : columns_(std::move(columns)) {}
  void reserve(std::size_t rows) { data_.reserve(rows * columns_.size()); }
  // Appends one row; its size must match the columns.
  void addRow(std::initializer_list<double> row);
  void addRow(const std::vector<double>& row);

  const std::vector<Column>& columns() const { return columns_; }
  std::size_t rows() const { return columns_.empty() ? 0 : data_.size() / columns_.size(); }
  double at(std::size_t row, std::size_t col) const { return data_[row * columns_.size() + col]; }
  std::size_t columnIndex(const std::string& name) const;  // throws if absent
  std::vector<double> column(const std::string& name) const;
  // Header "name [unit]", '\n' line ends; values with 10 significant digits, or exact (the
  // shortest text that reads back as the same double) once exact() was asked for.
  std::string csv() const;
  void exact(bool on = true) { exact_ = on; }

 private:
  std::vector<Column> columns_;
  std::vector<double> data_;
  bool exact_ = false;
};

}  // namespace needlesim::io
