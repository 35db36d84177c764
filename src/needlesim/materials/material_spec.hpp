#pragma once
// A tissue material as a scenario names it: a constitutive law, its parameters
// in SI, optional Prony terms and a density. The constitutive laws themselves
// (energies, stresses, tangents) live beside this file; this header is light
// so that the scenario reader and every engine can include it.
#include <limits>
#include <map>
#include <optional>
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

// The laws a scenario may name and the parameters each takes (materials/laws/).
const std::vector<std::string>& lawNames();
struct LawParam {
  std::string key;
  bool pressure;  // true: a modulus (Pa); false: dimensionless
  bool required;
  std::string help;  // what it is, as `needlesim schema` prints it
  double lo = -std::numeric_limits<double>::infinity(), hi = std::numeric_limits<double>::infinity();
  bool loOpen = false, hiOpen = false;  // the allowed range (lo, hi) or [lo, hi]
};
const std::vector<LawParam>& lawParams(const std::string& law);  // throws for unknown law
// Every parameter key of every law, once (its first declaration, with the help
// of every law that takes it), in the order the schema lists them: for each
// law, the volumetric K and nu, then its own.
const std::vector<LawParam>& lawParameterFields();

// A rule between a material section's parameters that the schema's ranges do
// not express (an Ogden term needs both mu_p and alpha_p), broken: the key, the
// value as given, why, and what is allowed.
struct ParamProblem {
  std::string key, value, why, allowed;
};
std::optional<ParamProblem> checkLawParams(const MaterialSpec& spec);  // nullopt: none broken

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
