#include "needlesim/results/forces_table.hpp"

#include <string>

#include "needlesim/core/error.hpp"

namespace needlesim::results {

std::vector<io::Column> ForcesTable::commonColumns(bool flexible) {
  std::vector<io::Column> c{{"time", "s"},          {"depth", "m"},         {"velocity", "m/s"},
                            {"force_total", "N"},   {"force_lateral", "N"}, {"tip_x", "m"},
                            {"tip_y", "m"},         {"tip_z", "m"}};
  if (flexible) c.push_back({"tip_deflection", "m"});
  return c;
}

namespace {
std::vector<io::Column> allColumns(bool flexible, const std::vector<io::Column>& extra) {
  auto c = ForcesTable::commonColumns(flexible);
  for (const auto& e : extra) {
    for (const auto& k : c)
      if (k.name == e.name) throw Error("forces table: the engine column '" + e.name + "' repeats a common column");
    c.push_back(e);
  }
  return c;
}
}  // namespace

ForcesTable::ForcesTable(bool flexible, std::vector<io::Column> extra)
    : flexible_(flexible), extra_(extra.size()), table_(allColumns(flexible, extra)) {
  row_.reserve(table_.columns().size());
}

template <class Values>
void ForcesTable::addRow(const NeedleForces& f, const Values& extra) {
  if (extra.size() != extra_)
    throw Error("forces table: " + std::to_string(extra.size()) + " engine values for " + std::to_string(extra_) +
                " engine columns");
  row_.assign({f.time, f.depth, f.velocity, f.force_total, f.force_lateral, f.tip_x, f.tip_y, f.tip_z});
  if (flexible_) row_.push_back(f.tip_deflection);
  row_.insert(row_.end(), extra.begin(), extra.end());
  table_.addRow(row_);
}

void ForcesTable::add(const NeedleForces& f, std::initializer_list<double> extra) { addRow(f, extra); }
void ForcesTable::add(const NeedleForces& f, const std::vector<double>& extra) { addRow(f, extra); }

}  // namespace needlesim::results
