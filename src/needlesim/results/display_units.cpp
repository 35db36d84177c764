#include "needlesim/results/display_units.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace needlesim::results {

std::string shownText(double value, std::string_view si_unit, const units::DisplayUnits& display,
                      std::string_view format, double largest) {
  if (std::isnan(value)) return "n/a";
  if (std::isinf(value)) return "none";
  const units::Shown s = units::shown(value, si_unit, display, largest);
  const std::string number = fmt::vformat(format, fmt::make_format_args(s.value));
  return s.unit == "1" || s.unit.empty() ? number : number + " " + s.unit;
}

std::string axisUnit(const std::string& label) {
  const auto open = label.rfind('[');
  if (open == std::string::npos || label.empty() || label.back() != ']') return {};
  return label.substr(open + 1, label.size() - open - 2);
}

namespace {
// The label with its bracketed unit replaced.
std::string relabel(const std::string& label, const std::string& unit) {
  return label.substr(0, label.rfind('[') + 1) + unit + "]";
}

// The largest finite magnitude of the plot's x (or y) values.
double largestOf(const io::Plot& plot, bool x) {
  double m = 0.0;
  for (const auto& s : plot.series)
    for (const double v : x ? s.x : s.y)
      if (std::isfinite(v)) m = std::max(m, std::abs(v));
  return m;
}

// The factor from the axis' unit to its display unit for values up to `largest` (1 when it
// stays); relabels the axis.
double axisFactor(std::string& label, const units::DisplayUnits& display, double largest) {
  const std::string from = axisUnit(label);
  if (from.empty()) return 1.0;
  const std::string to = display.unitFor(from, largest);
  if (to == from) return 1.0;
  label = relabel(label, to);
  return units::conversionFactor(from, to);
}

// Values in `unit`, scaled by `factor`, with round-off below 1e-9 of the largest shown as 0.
void scaleAxis(std::vector<double>& values, double factor, double largest) {
  for (double& v : values) {
    v *= factor;
    if (std::abs(v) < 1e-9 * largest * factor) v = 0.0;
  }
}
}  // namespace

io::Plot inDisplayUnits(io::Plot plot, const units::DisplayUnits& display) {
  const double lx = largestOf(plot, true), ly = largestOf(plot, false);
  const double fx = axisFactor(plot.xlabel, display, lx), fy = axisFactor(plot.ylabel, display, ly);
  for (auto& s : plot.series) {
    scaleAxis(s.x, fx, lx);
    scaleAxis(s.y, fy, ly);
  }
  for (auto& m : plot.xmarkers) m.x *= fx;
  return plot;
}

}  // namespace needlesim::results
