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

std::vector<int> cellRegions(const TissueSpec& t, const std::vector<double>& points, int dim,
                             const std::vector<int>& conn, int perCell) {
  std::vector<int> out(conn.size() / static_cast<std::size_t>(perCell));
  if (t.geometry && t.geometry->region.size() == out.size()) return t.geometry->region;  // the mesh's own
  for (std::size_t e = 0; e < out.size(); ++e) {
    double c[3] = {0.0, 0.0, 0.0};
    for (int a = 0; a < perCell; ++a) {
      const auto node = static_cast<std::size_t>(conn[e * static_cast<std::size_t>(perCell) + static_cast<std::size_t>(a)]);
      for (int k = 0; k < dim; ++k) c[k] += points[node * static_cast<std::size_t>(dim) + static_cast<std::size_t>(k)] / perCell;
    }
    out[e] = regionAt(t, c[0], c[1], c[2]);
  }
  return out;
}

std::string regionLegend(const TissueSpec& t) {
  std::vector<std::string> names;
  for (const auto& L : t.layers) names.push_back(L.name);
  for (const auto& I : t.inclusions) names.push_back(I.name);
  std::string legend;
  for (std::size_t i = 0; i < names.size(); ++i)
    legend += fmt::format("{}{} {}", i ? ", " : "", i, names[i].empty() ? fmt::format("region{}", i) : names[i]);
  return legend;
}

}  // namespace needlesim::tissue
