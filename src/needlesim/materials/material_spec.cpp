#include "needlesim/materials/material_spec.hpp"

#include <stdexcept>

#include "needlesim/core/error.hpp"
#include "needlesim/materials/elastic_moduli.hpp"

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

const std::vector<std::string>& lawNames() {
  static const std::vector<std::string> names{"linear", "neo-hookean", "mooney-rivlin",
                                              "yeoh",   "ogden",       "fung"};
  return names;
}

const std::vector<LawParam>& lawParams(const std::string& law) {
  // Volumetric part: bulk modulus K or Poisson ratio nu (one of them, nu < 0.5).
  static const LawParam K{"K", true, false, "bulk modulus (or give nu)"};
  static const LawParam nu{"nu", false, false, "Poisson ratio, -1 < nu < 0.5 (or give K)"};
  static const std::map<std::string, std::vector<LawParam>> table{
      {"linear",
       {{"E", true, true, "Young's modulus"}, {"nu", false, true, "Poisson ratio, -1 < nu < 0.5"}}},
      {"neo-hookean", {{"C10", true, true, "W = C10 (I1bar - 3) + U(J)"}, K, nu}},
      {"mooney-rivlin",
       {{"C10", true, true, "coefficient of (I1bar - 3)"},
        {"C01", true, true, "coefficient of (I2bar - 3)"},
        K,
        nu}},
      {"yeoh",
       {{"C10", true, true, "coefficient of (I1bar - 3)"},
        {"C20", true, false, "coefficient of (I1bar - 3)^2"},
        {"C30", true, false, "coefficient of (I1bar - 3)^3"},
        K,
        nu}},
      {"ogden",
       {{"mu1", true, true, "shear-like modulus of term 1"},
        {"alpha1", false, true, "exponent of term 1"},
        {"mu2", true, false, "term 2"},
        {"alpha2", false, false, "term 2"},
        {"mu3", true, false, "term 3"},
        {"alpha3", false, false, "term 3"},
        K,
        nu}},
      {"fung",
       {{"mu", true, true, "Fung-Demiray modulus (seed 000 eq 8)"},
        {"gamma", false, true, "Fung-Demiray exponent, > 0 (seed 000 eq 8)"},
        K,
        nu}},
  };
  auto it = table.find(law);
  if (it == table.end()) throw Error("unknown constitutive law '" + law + "'");
  return it->second;
}

double SmallStrainModuli::youngs() const { return youngPoisson(bulk, shear).E; }
double SmallStrainModuli::poisson() const { return youngPoisson(bulk, shear).nu; }

SmallStrainModuli smallStrainModuli(const MaterialSpec& m) {
  SmallStrainModuli s;
  if (m.law == "linear") {
    double E = m.param("E"), nu = m.param("nu");
    s.shear = lame(E, nu).mu;
    s.bulk = bulkModulus(E, nu);
    return s;
  }
  if (m.law == "neo-hookean" || m.law == "yeoh") {
    s.shear = 2.0 * m.param("C10");
  } else if (m.law == "mooney-rivlin") {
    s.shear = 2.0 * (m.param("C10") + m.param("C01"));
  } else if (m.law == "ogden") {
    for (int i = 1; i <= 3; ++i) {
      auto k = std::to_string(i);
      if (m.has("mu" + k)) s.shear += 0.5 * m.param("mu" + k) * m.paramOr("alpha" + k, 2.0);
    }
  } else if (m.law == "fung") {
    s.shear = m.param("mu");  // dW/dI1 at I1 = 3 is mu/2 (seed 000 eq 8)
  } else {
    lawParams(m.law);  // throws for an unknown law
  }
  if (m.has("K")) {
    s.bulk = m.param("K");
  } else {
    double nu = m.paramOr("nu", 0.49);
    s.bulk = bulkFromShear(s.shear, nu);
  }
  return s;
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
