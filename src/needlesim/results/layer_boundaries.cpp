#include "needlesim/results/layer_boundaries.hpp"

#include <fmt/format.h>

#include <cmath>

#include "needlesim/core/units.hpp"
#include "needlesim/results/display_units.hpp"

namespace needlesim::results {

void markLayerBoundaries(io::Plot& plot, const Scenario& scenario, double axis_origin) {
  const auto& layers = scenario.tissue.layers;
  if (layers.size() < 2) return;
  const std::string unit = axisUnit(plot.xlabel);
  const double toAxis = unit.empty() ? 1.0 : units::conversionFactor("m", unit);
  const double alongNeedle = 1.0 / std::sin(scenario.insertion.entry_angle);
  double depth = 0.0;
  for (std::size_t i = 0; i + 1 < layers.size(); ++i) {
    depth += layers[i].thickness;
    plot.xmarkers.push_back({(depth * alongNeedle - axis_origin) * toAxis, fmt::format("{} | {}", layers[i].name, layers[i + 1].name)});
  }
}

}  // namespace needlesim::results
