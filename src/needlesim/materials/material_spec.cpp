#include "needlesim/materials/material_spec.hpp"

#include <stdexcept>

#include "needlesim/core/error.hpp"
#include "needlesim/materials/elastic_moduli.hpp"
#include "needlesim/materials/laws/law_unit.hpp"

namespace needlesim::materials {

double MaterialSpec::param(const std::string& key) const {
  auto it = params.find(key);
  if (it == params.end()) throw Error("material '" + name + "' (" + law + ") has no parameter " + key);
  return it->second;
}

double MaterialSpec::paramOr(const std::string& key, double fallback) const {
  auto it = params.find(key);
  return it == params.end() ? fallback : it->second;
}

double SmallStrainModuli::youngs() const { return youngPoisson(bulk, shear).E; }
double SmallStrainModuli::poisson() const { return youngPoisson(bulk, shear).nu; }

// The law's own formula (laws/) at the spec's parameters, unchecked: the reader
// calls it to refuse a non-positive modulus with its own message.
SmallStrainModuli smallStrainModuli(const MaterialSpec& m) {
  const LawUnit& u = lawUnit(m.law);
  Hyperelastic h;
  h.kind = u.kind;
  u.read(m, h);
  if (u.volumetric) h.bulk = m.has("K") ? m.param("K") : bulkFromShear(u.shear(h), m.paramOr("nu", 0.49));
  return smallStrainModuli(h);
}

const std::map<std::string, MaterialSpec>& materialLibrary() {
  static const std::map<std::string, MaterialSpec> lib = [] {
    std::map<std::string, MaterialSpec> l;
    auto add = [&](const std::string& name, const std::string& law,
                   std::map<std::string, double> p, double rho) {
      MaterialSpec m;
      m.name = name;
      m.law = law;
      m.params = std::move(p);
      m.density = rho;
      l[name] = m;
    };
    // seed 003 section 5.1: 10 wt% gelatin, E = 30.74 kPa, nu = 0.422,
    // density 0.489 kg / (0.120 x 0.080 x 0.055 m^3) = 636.72 kg/m^3.
    add("gelatin_10wt", "linear", {{"E", 30.74e3}, {"nu", 0.422}}, 636.71875);
    // seed 004 Table I: neo-Hookean C10 from compression; nu = 0.45 as in its section IV.
    add("plastisol_soft", "neo-hookean", {{"C10", 3.6e3}, {"nu", 0.45}}, 1000.0);
    add("plastisol_hard", "neo-hookean", {{"C10", 4.0e3}, {"nu", 0.45}}, 1000.0);
    add("porcine_gel", "neo-hookean", {{"C10", 4.9e3}, {"nu", 0.45}}, 1000.0);
    add("chicken_breast", "neo-hookean", {{"C10", 3.7e3}, {"nu", 0.45}}, 1050.0);
    return l;
  }();
  return lib;
}

}  // namespace needlesim::materials
