// The registry of constitutive laws (law_list.hpp) and what every law shares:
// lookup by name and kind, the parameter lists the schema and the reader use,
// the volumetric part and the small-strain moduli.
#include <map>
#include <sstream>

#include "needlesim/core/error.hpp"
#include "needlesim/materials/laws/law_unit.hpp"

namespace needlesim::materials {

const std::vector<const LawUnit*>& lawUnits() {
#define NEEDLESIM_LAW_ENTRY(kind, fn) &laws::fn(),
  static const std::vector<const LawUnit*> all{NEEDLESIM_LAWS(NEEDLESIM_LAW_ENTRY)};
#undef NEEDLESIM_LAW_ENTRY
  return all;
}

const LawUnit& lawUnit(LawKind kind) { return *lawUnits().at(static_cast<std::size_t>(kind)); }

const LawUnit* findLawUnit(const std::string& name) {
  for (const LawUnit* u : lawUnits())
    if (u->name == name) return u;
  return nullptr;
}

const LawUnit& lawUnit(const std::string& name) {
  if (const LawUnit* u = findLawUnit(name)) return *u;
  std::string allowed;
  for (const auto& n : lawNames()) allowed += (allowed.empty() ? "" : ", ") + n;
  throw Error("unknown constitutive law '" + name + "'; allowed: " + allowed);
}

const std::vector<std::string>& lawNames() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> v;
    for (const LawUnit* u : lawUnits()) v.push_back(u->name);
    return v;
  }();
  return names;
}

const std::vector<LawParam>& volumetricParams() {
  static const std::vector<LawParam> v{
      laws::positiveParam("K", true, false, "bulk modulus of a hyperelastic law (instead of nu)"),
      {"nu", false, false, "Poisson ratio (linear; or the volumetric part of a hyperelastic law)", -1.0, 0.5, true,
       true}};
  return v;
}

const std::vector<LawParam>& lawParams(const std::string& law) {
  static const std::map<std::string, std::vector<LawParam>> table = [] {
    std::map<std::string, std::vector<LawParam>> t;
    for (const LawUnit* u : lawUnits()) {
      auto& v = t[u->name] = u->params;
      if (u->volumetric) v.insert(v.end(), volumetricParams().begin(), volumetricParams().end());
    }
    return t;
  }();
  auto it = table.find(law);
  if (it == table.end()) throw Error("unknown constitutive law '" + law + "'");
  return it->second;
}

const std::vector<LawParam>& lawParameterFields() {
  static const std::vector<LawParam> fields = [] {
    std::vector<LawParam> v;
    auto add = [&](const LawParam& p) {
      for (auto& q : v)
        if (q.key == p.key) {  // a key several laws take: each meaning once
          if (q.help.find(p.help) == std::string::npos) q.help += "; " + p.help;
          return;
        }
      v.push_back(p);
    };
    for (const LawUnit* u : lawUnits()) {
      if (u->volumetric)
        for (const auto& p : volumetricParams()) add(p);
      for (const auto& p : u->params) add(p);
    }
    return v;
  }();
  return fields;
}

SmallStrainModuli smallStrainModuli(const Hyperelastic& h) {
  const LawUnit& u = lawUnit(h.kind);
  SmallStrainModuli s;
  s.shear = u.shear(h);
  s.bulk = u.volumetric ? h.bulk : u.bulk(h);
  return s;
}

std::optional<ParamProblem> checkLawParams(const MaterialSpec& spec) {
  const LawUnit& u = lawUnit(spec.law);
  return u.check ? u.check(spec) : std::nullopt;
}

namespace laws {

namespace {
LawParam ranged(std::string key, bool pressure, bool required, std::string help, double lo, bool loOpen) {
  LawParam p{std::move(key), pressure, required, std::move(help)};
  p.lo = lo;
  p.loOpen = loOpen;
  return p;
}
}  // namespace

LawParam positiveParam(std::string key, bool pressure, bool required, std::string help) {
  return ranged(std::move(key), pressure, required, std::move(help), 0.0, true);
}
LawParam nonNegativeParam(std::string key, bool pressure, bool required, std::string help) {
  return ranged(std::move(key), pressure, required, std::move(help), 0.0, false);
}
LawParam anyParam(std::string key, bool pressure, bool required, std::string help) {
  return LawParam{std::move(key), pressure, required, std::move(help)};
}
LawParam c10Param() { return positiveParam("C10", true, true, "neo-Hookean / Mooney-Rivlin / Yeoh first coefficient"); }

std::string numberText(double v) {
  std::ostringstream s;
  s.precision(6);
  s << v;
  return s.str();
}

void badParam(const std::string& law, const std::string& key, double v, const std::string& allowed) {
  throw Error("material law '" + law + "': parameter " + key + " = " + numberText(v) + " is not allowed; " + allowed);
}

void requireFinite(const std::string& law, const std::string& key, double v) {
  if (!std::isfinite(v)) badParam(law, key, v, "it must be a finite number");
}

}  // namespace laws
}  // namespace needlesim::materials
