// Tissue regions (regions.hpp): layers then inclusions, with material, friction and toughness.
#include "needlesim/tissue/regions.hpp"

#include <algorithm>
#include <fmt/format.h>

namespace needlesim::tissue {

std::vector<Region> regions(const TissueSpec& t) {
  std::vector<Region> out;
  for (std::size_t i = 0; i < t.layers.size(); ++i) {
    const auto& l = t.layers[i];
    out.push_back({l.name, fmt::format("tissue.layers[{}]", i), l.material, l.friction.coefficient, l.toughness, false});
  }
  for (std::size_t i = 0; i < t.inclusions.size(); ++i) {
    const auto& c = t.inclusions[i];
    out.push_back({c.name, fmt::format("tissue.inclusions[{}]", i), c.material, c.friction_coefficient, c.toughness, true});
  }
  return out;
}

std::vector<materials::MaterialSpec> regionMaterials(const std::vector<Region>& r) {
  std::vector<materials::MaterialSpec> out;
  for (const auto& x : r) out.push_back(x.material);
  return out;
}

std::vector<double> regionFrictions(const std::vector<Region>& r) {
  std::vector<double> out;
  for (const auto& x : r) out.push_back(x.friction);
  return out;
}

bool uniformFriction(const std::vector<Region>& r) {
  return std::all_of(r.begin(), r.end(), [&](const Region& x) { return x.friction == r.front().friction; });
}

int regionAt(const TissueSpec& t, double x, double y, double z) {
  for (int i = static_cast<int>(t.inclusions.size()) - 1; i >= 0; --i)
    if (t.inclusions[i].contains(x, y, z)) return static_cast<int>(t.layers.size()) + i;
  return static_cast<int>(t.layerAt(x));
}

}  // namespace needlesim::tissue
