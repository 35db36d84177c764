#include "needlesim/core/units.hpp"

#include <array>
#include <cctype>
#include <charconv>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

#include <fmt/format.h>

#include "needlesim/core/error.hpp"

namespace needlesim::units {
namespace {

struct UnitDef {
  std::string_view symbol;
  double factor;
  Dim dim;
};

// Base symbols; SI prefixes are applied to those marked prefixable below.
constexpr std::array<UnitDef, 16> kUnits{{
    {"m", 1.0, dim::Length},
    {"g", 1e-3, dim::Mass},
    {"s", 1.0, dim::Time},
    {"N", 1.0, dim::Force},
    {"Pa", 1.0, dim::Pressure},
    {"J", 1.0, {2, 1, -2, 0}},
    {"W", 1.0, {2, 1, -3, 0}},
    {"Hz", 1.0, dim::Frequency},
    {"rad", 1.0, dim::Angle},
    {"deg", std::numbers::pi / 180.0, dim::Angle},
    {"min", 60.0, dim::Time},
    {"h", 3600.0, dim::Time},
    {"rev", 2.0 * std::numbers::pi, dim::Angle},
    {"rpm", 2.0 * std::numbers::pi / 60.0, dim::AngularVelocity},
    {"%", 0.01, dim::None},
    {"L", 1e-3, {3, 0, 0, 0}},
}};

constexpr bool prefixable(std::string_view s) {
  return s == "m" || s == "g" || s == "s" || s == "N" || s == "Pa" || s == "J" || s == "W" ||
         s == "Hz" || s == "rad" || s == "L";
}

double prefixFactor(std::string_view p) {
  if (p == "n") return 1e-9;
  if (p == "u" || p == "\xC2\xB5" || p == "\xCE\xBC") return 1e-6;
  if (p == "m") return 1e-3;
  if (p == "c") return 1e-2;
  if (p == "k") return 1e3;
  if (p == "M") return 1e6;
  if (p == "G") return 1e9;
  return 0.0;
}

Dim scale(Dim d, int e) { return {d.L * e, d.M * e, d.T * e, d.A * e}; }
Dim add(Dim a, Dim b) { return {a.L + b.L, a.M + b.M, a.T + b.T, a.A + b.A}; }

// One unit symbol, possibly prefixed: "mm", "kPa", "deg".
bool lookup(std::string_view sym, double& factor, Dim& d) {
  if (sym == "1") {  // as in "1/s"
    factor = 1.0;
    d = dim::None;
    return true;
  }
  for (const auto& u : kUnits)
    if (u.symbol == sym) {
      factor = u.factor;
      d = u.dim;
      return true;
    }
  // Prefixes are one character, or two bytes for the micro sign.
  for (std::size_t plen : {std::size_t{1}, std::size_t{2}}) {
    if (sym.size() <= plen) continue;
    double pf = prefixFactor(sym.substr(0, plen));
    if (pf == 0.0) continue;
    auto base = sym.substr(plen);
    if (!prefixable(base)) continue;
    for (const auto& u : kUnits)
      if (u.symbol == base) {
        factor = pf * u.factor;
        d = u.dim;
        return true;
      }
  }
  return false;
}

std::string_view trim(std::string_view s) {
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.remove_suffix(1);
  return s;
}

}  // namespace

Quantity parse(std::string_view text) {
  std::string_view s = trim(text);
  if (s.empty()) throw std::invalid_argument("empty value");
  double value = 0.0;
  const char* begin = s.data();
  const char* end = s.data() + s.size();
  if (*begin == '+') ++begin;
  auto [ptr, ec] = std::from_chars(begin, end, value);
  if (ec == std::errc::result_out_of_range)
    throw std::invalid_argument("is a number out of range of a double (magnitudes from about 2.2e-308 to 1.8e308)");
  if (ec != std::errc() || ptr == begin) throw std::invalid_argument("does not start with a number");
  if (!std::isfinite(value)) throw std::invalid_argument("is not a finite number");
  std::string_view rest = trim(std::string_view(ptr, static_cast<std::size_t>(end - ptr)));
  Quantity q;
  q.value = value;
  if (rest.empty()) return q;  // dimensionless
  q.unit = std::string(rest);
  if (rest == "G") {
    q.gauge = true;
    return q;
  }
  double factor = 1.0;
  Dim d{};
  bool divide = false;
  std::size_t i = 0;
  while (i < rest.size()) {
    char c = rest[i];
    if (c == ' ' || c == '*' || c == '.') {
      ++i;
      continue;
    }
    if (c == '/') {
      if (divide) throw std::invalid_argument("has more than one '/' in its unit; write e.g. 'N s/m^2'");
      divide = true;
      ++i;
      continue;
    }
    std::size_t j = i;
    while (j < rest.size() && rest[j] != ' ' && rest[j] != '*' && rest[j] != '/' && rest[j] != '^')
      ++j;
    std::string_view sym = rest.substr(i, j - i);
    int exponent = 1;
    if (j < rest.size() && rest[j] == '^') {
      std::size_t k = j + 1;
      if (k < rest.size() && (rest[k] == '-' || rest[k] == '+')) ++k;
      while (k < rest.size() && std::isdigit(static_cast<unsigned char>(rest[k]))) ++k;
      std::string exp(rest.substr(j + 1, k - j - 1));
      if (exp.empty() || exp == "-" || exp == "+")
        throw std::invalid_argument("has an exponent without digits after '^'");
      if (exp.size() > 3) throw std::invalid_argument("has an exponent '^" + exp + "' beyond any unit's");
      exponent = std::stoi(exp);
      j = k;
    }
    double f = 1.0;
    Dim ud{};
    if (!lookup(sym, f, ud))
      throw std::invalid_argument("has an unknown unit '" + printable(sym) + "'");
    if (divide) exponent = -exponent;
    factor *= std::pow(f, exponent);
    d = add(d, scale(ud, exponent));
    i = j;
  }
  q.value = value * factor;
  q.dim = d;
  return q;
}

std::string siName(const Dim& d) {
  if (d == dim::None) return "1";
  if (d == dim::Length) return "m";
  if (d == dim::Mass) return "kg";
  if (d == dim::Time) return "s";
  if (d == dim::Angle) return "rad";
  if (d == dim::Velocity) return "m/s";
  if (d == dim::AngularVelocity) return "rad/s";
  if (d == dim::Frequency) return "Hz";
  if (d == dim::Force) return "N";
  if (d == dim::Moment) return "N m";
  if (d == dim::Pressure) return "Pa";
  if (d == dim::Density) return "kg/m^3";
  if (d == dim::ForcePerLength) return "N/m";
  if (d == dim::ForceTimePerArea) return "N s/m^2";
  if (d == dim::ForceTimePerLength) return "N s/m";
  if (d == dim::TorqueTimePerAngle) return "N m s/rad";
  if (d == Dim{-2, 1, -2, 0}) return "N/m^3";  // spring support stiffness per area
  std::string s;
  auto part = [&](const char* sym, int e) {
    if (e == 0) return;
    if (!s.empty()) s += " ";
    s += sym;
    if (e != 1) {
      s += '^';
      s += std::to_string(e);
    }
  };
  part("kg", d.M);
  part("m", d.L);
  part("s", d.T);
  part("rad", d.A);
  return s;
}

std::string examples(const Dim& d) {
  if (d == dim::None) return "a plain number";
  if (d == dim::Length) return "m, mm, um, cm";
  if (d == dim::Time) return "s, ms, min";
  if (d == dim::Angle) return "deg, rad";
  if (d == dim::Velocity) return "mm/s, m/s";
  if (d == dim::AngularVelocity) return "deg/s, rad/s, rpm";
  if (d == dim::Frequency) return "Hz, kHz";
  if (d == dim::Force) return "N, mN";
  if (d == dim::Moment) return "N m, N mm";
  if (d == dim::Pressure) return "Pa, kPa, MPa, GPa";
  if (d == dim::Density) return "kg/m^3, g/cm^3";
  if (d == dim::ForcePerLength) return "N/m, N/mm, J/m^2";
  if (d == dim::ForceTimePerArea) return "N s/m^2, N s/mm^2";
  if (d == Dim{-2, 1, -2, 0}) return "N/m^3, N/mm^3";
  return siName(d);
}

std::string inUnitOf(double si, const Dim& d, std::string_view written) {
  try {
    const Quantity q = parse(written);
    const Quantity one = parse("1 " + q.unit);
    if (!q.unit.empty() && !q.gauge && one.dim == d) return fmt::format("{:g} {}", si / one.value, q.unit);
  } catch (const std::invalid_argument&) {
  }
  return fmt::format("{:g} {}", si, siName(d));
}

const std::vector<DisplayDimension>& displayDimensions() {
  static const std::vector<DisplayDimension> table = {
      {"length", dim::Length, "m", {"m", "cm", "mm", "um", "nm"}, {"m", "mm", "um", "nm"}},
      {"force", dim::Force, "N", {"N", "kN", "mN", "uN"}, {"kN", "N", "mN", "uN"}},
      {"stress", dim::Pressure, "Pa", {"Pa", "kPa", "MPa", "GPa"}, {"GPa", "MPa", "kPa", "Pa"}},
      {"velocity", dim::Velocity, "m/s", {"m/s", "cm/s", "mm/s", "um/s"}, {"m/s", "mm/s", "um/s"}},
      {"angle", dim::Angle, "rad", {"rad", "deg", "mrad"}},
      {"time", dim::Time, "s", {"s", "ms", "us", "min", "h"}, {"s", "min", "h", "ms", "us"}},
      {"mass", dim::Mass, "kg", {"kg", "g", "mg"}, {"kg", "g", "mg"}},
      {"energy", dim::Energy, "J", {"J", "kJ", "mJ", "uJ"}, {"kJ", "J", "mJ", "uJ"}},
      {"moment", dim::Moment, "N m", {"N m", "N mm", "mN m"}, {"N m", "N mm"}},
      {"angular_velocity", dim::AngularVelocity, "rad/s", {"rad/s", "deg/s", "rpm"}},
  };
  return table;
}

const DisplayDimension* findDisplayDimension(std::string_view name) {
  for (const auto& d : displayDimensions())
    if (d.name == name) return &d;
  return nullptr;
}

const DisplayDimension* displayDimensionOfUnit(std::string_view unit) {
  for (const auto& d : displayDimensions())
    for (const auto u : d.units)
      if (u == unit) return &d;
  return nullptr;
}

void DisplayUnits::set(std::string_view dimension, std::string unit) {
  if (!fixed(dimension)) fixed_.emplace_back(dimension);
  prefer(dimension, std::move(unit));
}

bool DisplayUnits::fixed(std::string_view dimension) const {
  return std::find(fixed_.begin(), fixed_.end(), dimension) != fixed_.end();
}

void DisplayUnits::prefer(std::string_view dimension, std::string unit) {
  for (auto& [d, u] : units_)
    if (d == dimension) {
      u = std::move(unit);
      return;
    }
  units_.emplace_back(std::string(dimension), std::move(unit));
}

std::string DisplayUnits::unitFor(std::string_view unit) const {
  const DisplayDimension* d = displayDimensionOfUnit(unit);
  if (!d) return std::string(unit);
  for (const auto& [name, u] : units_)
    if (name == d->name) return u;
  return std::string(d->si);
}

std::vector<std::pair<std::string, std::string>> DisplayUnits::chosen() const {
  std::vector<std::pair<std::string, std::string>> out;
  for (const auto& d : displayDimensions())
    for (const auto& [name, u] : units_)
      if (name == d.name) out.emplace_back(name, u);
  return out;
}

double conversionFactor(std::string_view from, std::string_view to) {
  const Quantity a = parse("1 " + std::string(from)), b = parse("1 " + std::string(to));
  if (!(a.dim == b.dim)) throw Error(fmt::format("cannot convert {} to {}: different dimensions", from, to));
  return a.value / b.value;
}

namespace {
// Whether a magnitude reads well: in [lo, 1000).
bool readable(double shown, double lo) { return shown >= lo && shown < 1000.0; }
// Below this fraction of its scale a value is round-off and shown as 0.
constexpr double kRoundOff = 1e-9;
}  // namespace

std::string DisplayUnits::unitFor(std::string_view unit, double largest) const {
  const std::string preferred = unitFor(unit);
  const DisplayDimension* d = displayDimensionOfUnit(unit);
  if (!d || fixed(d->name) || d->rescaled.empty() || !std::isfinite(largest) || largest == 0.0) return preferred;
  const double inPreferred = std::abs(largest) * conversionFactor(unit, preferred);
  if (inPreferred < kRoundOff || readable(inPreferred, 0.1)) return preferred;
  for (const double lo : {1.0, 0.1})
    for (const auto candidate : d->rescaled)
      if (readable(std::abs(largest) * conversionFactor(unit, candidate), lo)) return std::string(candidate);
  return preferred;
}

Shown shown(double value, std::string_view unit, const DisplayUnits& display, double largest) {
  const bool single = !(largest > 0.0) || !std::isfinite(largest);
  const std::string target = display.unitFor(unit, single ? std::abs(value) : largest);
  const double factor = target == unit ? 1.0 : conversionFactor(unit, target);
  double v = value * factor;
  const double scale = single ? 1.0 : largest * factor;  // a single value: one unit it is shown in
  if (std::isfinite(v) && std::abs(v) < kRoundOff * scale) v = 0.0;
  return {v == 0.0 ? 0.0 : v, target};
}

std::optional<GaugeSize> gaugeSize(int gauge) {
  // Nominal outer diameter (mm) and regular-wall inner diameter (mm), ISO 9626.
  struct Row {
    int g;
    double od, id;
  };
  static constexpr Row rows[] = {
      {10, 3.404, 2.693}, {11, 3.048, 2.388}, {12, 2.769, 2.159}, {13, 2.413, 1.804},
      {14, 2.108, 1.600}, {15, 1.829, 1.372}, {16, 1.651, 1.194}, {17, 1.473, 1.067},
      {18, 1.270, 0.838}, {19, 1.067, 0.686}, {20, 0.908, 0.603}, {21, 0.819, 0.514},
      {22, 0.718, 0.413}, {23, 0.642, 0.337}, {24, 0.566, 0.311}, {25, 0.515, 0.260},
      {26, 0.464, 0.260}, {27, 0.413, 0.210}, {28, 0.362, 0.184}, {29, 0.337, 0.184},
      {30, 0.312, 0.159}, {31, 0.261, 0.133}, {32, 0.235, 0.108}, {33, 0.210, 0.108},
      {34, 0.159, 0.0826}};
  for (const auto& r : rows)
    if (r.g == gauge) return GaugeSize{r.g, r.od * 1e-3, r.id * 1e-3};
  return std::nullopt;
}

}  // namespace needlesim::units
