#pragma once
// The explicit engine's tables in tests: forces.csv, energy.csv, contact.csv, seam.csv (explicit_outputs.cpp).
#include <string>
#include <vector>

#include "needlesim/engines/memory_sink.hpp"

namespace needlesim::explicit_test {

inline std::vector<double> column(const MemorySink& m, const std::string& table, const std::string& name) {
  return m.tables.at(table).column(name);
}
// Needle displacement: the depth travelled since the start.
inline std::vector<double> needleDisplacement(const MemorySink& m) {
  auto d = column(m, "forces", "depth");
  const double d0 = d.empty() ? 0.0 : d.front();
  for (double& v : d) v -= d0;
  return d;
}

}  // namespace needlesim::explicit_test
