#pragma once
// A tissue material as a scenario names it: a constitutive law, its parameters
// in SI, optional Prony terms and a density. The constitutive laws themselves
// (energies, stresses, tangents) live beside this file; this header is light
// so that the scenario reader and every engine can include it.
#include <map>
#include <string>
#include <vector>

namespace needlesim::materials {

// One term of a Prony series: relative modulus g_i and relaxation time tau_i
// (seed 001 eqs 1-4, read as quasi-linear viscoelasticity).
struct PronyTerm {
  double g = 0.0;
  double tau = 0.0;  // s
};

struct MaterialSpec {
  std::string name = "custom";           // library name, or "custom"
  std::string law = "linear";            // see lawNames()
  std::map<std::string, double> params;  // SI values: E, nu, K, C10, C01, C20, C30, mu1.., alpha1.., mu, gamma
  std::vector<PronyTerm> prony;
  double density = 1000.0;  // kg/m^3

  double param(const std::string& key) const;            // throws if absent
  double paramOr(const std::string& key, double fallback) const;
  bool has(const std::string& key) const { return params.count(key) != 0; }
};

// The laws a scenario may name and the parameters each takes.
const std::vector<std::string>& lawNames();
struct LawParam {
  std::string key;
  bool pressure;  // true: a modulus (Pa); false: dimensionless
  bool required;
  std::string meaning;
};
const std::vector<LawParam>& lawParams(const std::string& law);  // throws for unknown law

// Small-strain moduli of any law (the limit every law must reach):
// initial shear modulus mu0 and bulk modulus K (from K, or from nu).
struct SmallStrainModuli {
  double shear = 0.0;  // Pa
  double bulk = 0.0;   // Pa
  double youngs() const;
  double poisson() const;
};
SmallStrainModuli smallStrainModuli(const MaterialSpec& m);

// Built-in library of the seeds' materials (name -> spec). See docs/models/materials.md.
const std::map<std::string, MaterialSpec>& materialLibrary();

}  // namespace needlesim::materials
