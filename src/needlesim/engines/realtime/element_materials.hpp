#pragma once
// Element materials of the real-time tissues (realtime2d, realtime3d): by the depth band
// (layer) of the element centre, then the material regions (bonded inclusions) holding it.
#include <fmt/format.h>

#include <string>
#include <utility>
#include <vector>

#include "needlesim/core/error.hpp"

namespace needlesim::realtime {

// Material of an element with centre c: `base`, or the layer whose band holds c.x() (layers:
// x of each band's far boundary, ascending), then the last region whose ball holds c; hit[r]
// tells whether region r holds it.
template <class Vec, class Material, class Region>
Material materialAt(const Vec& c, const Material& base, const std::vector<std::pair<double, Material>>& layers,
                    const std::vector<Region>& regions, std::vector<bool>& hit) {
  Material m = base;
  if (!layers.empty()) {
    std::size_t L = 0;
    while (L + 1 < layers.size() && c.x() > layers[L].first) ++L;
    m = layers[L].second;
  }
  hit.assign(regions.size(), false);
  for (std::size_t r = 0; r < regions.size(); ++r) {
    if ((c - regions[r].centre).norm() > regions[r].radius) continue;
    hit[r] = true;
    m = regions[r].material;
  }
  return m;
}

// Every region must hold an element centre (else its material would be lost silently).
template <class Region>
void requireRegionsMeshed(const std::string& engine, const std::vector<Region>& regions,
                          const std::vector<std::vector<int>>& region_nodes) {
  for (std::size_t r = 0; r < regions.size(); ++r)
    if (region_nodes[r].empty())
      throw SolverError(fmt::format("{}: material region {} (radius {:g} mm) holds no element centre of the "
                                    "mesh; refine the mesh or enlarge the region",
                                    engine, r, regions[r].radius * 1e3));
}

}  // namespace needlesim::realtime
