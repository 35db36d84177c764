// Default texts and schema rows of the parameter tables (parameter_table.hpp).
#include "needlesim/scenario/parameter_table.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <stdexcept>

namespace needlesim::scenario {
namespace {
// "1e+06" -> "1e6", "2.5e-05" -> "2.5e-5": an exponent as a user writes it.
std::string compactExponent(std::string t) {
  const auto e = t.find('e');
  if (e == std::string::npos) return t;
  std::string exponent = t.substr(e + 1);
  const bool negative = exponent[0] == '-';
  exponent.erase(0, exponent.find_first_not_of("+-"));
  exponent.erase(0, std::min(exponent.find_first_not_of('0'), exponent.size() - 1));
  return t.substr(0, e + 1) + (negative ? "-" : "") + exponent;
}
}  // namespace

std::string defaultText(double si, const units::Dim& dim, const std::string& unit) {
  const auto readsBack = [&](const std::string& text) {
    try {
      return units::parse(text).value == si;
    } catch (const std::invalid_argument&) {
      return false;
    }
  };
  if (unit.empty()) {
    const std::string t = compactExponent(fmt::format("{:g}", si));
    return readsBack(t) ? t : fmt::format("{}", si);
  }
  const double scale = units::parse("1 " + unit).value;
  const std::string t = fmt::format("{:g} {}", si / scale, unit);
  if (readsBack(t)) return t;
  const std::string exact = fmt::format("{} {}", si / scale, unit);
  return readsBack(exact) ? exact : fmt::format("{} {}", si, units::siName(dim));
}

FieldDoc numberDoc(const std::string& type, const std::string& key, const units::Dim& dim, Range r,
                   std::string default_text, std::string help) {
  FieldDoc f;
  f.section = type;
  f.key = key;
  f.kind = dim == units::dim::None ? Kind::Number : Kind::Quantity;
  f.dim = dim;
  f.default_text = std::move(default_text);
  f.lo = r.lo;
  f.hi = r.hi;
  f.lo_open = r.lo_open;
  f.hi_open = r.hi_open;
  f.help = std::move(help);
  return f;
}

}  // namespace needlesim::scenario
