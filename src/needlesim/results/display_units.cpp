#include "needlesim/results/display_units.hpp"

#include <fmt/format.h>

#include <cmath>

namespace needlesim::results {

std::string shownText(double value, std::string_view si_unit, const units::DisplayUnits& display,
                      std::string_view format) {
  if (!std::isfinite(value)) return "n/a";
  const units::Shown s = units::shown(value, si_unit, display);
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

// The factor from the axis' unit to its display unit (1 when it stays); relabels the axis.
double axisFactor(std::string& label, const units::DisplayUnits& display) {
  const std::string from = axisUnit(label);
  if (from.empty()) return 1.0;
  const std::string to = display.unitFor(from);
  if (to == from) return 1.0;
  label = relabel(label, to);
  return units::conversionFactor(from, to);
}
}  // namespace

io::Plot inDisplayUnits(io::Plot plot, const units::DisplayUnits& display) {
  const double fx = axisFactor(plot.xlabel, display), fy = axisFactor(plot.ylabel, display);
  for (auto& s : plot.series) {
    for (double& x : s.x) x *= fx;
    for (double& y : s.y) y *= fy;
  }
  for (auto& m : plot.xmarkers) m.x *= fx;
  return plot;
}

}  // namespace needlesim::results
