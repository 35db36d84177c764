// The registry of constitutive laws (materials/laws/): the laws and parameters
// it declares are the scenario schema's, and each law's small-strain moduli
// agree with the second derivatives of its own strain energy.
#include <gtest/gtest.h>

#include <map>
#include <set>
#include <sstream>

#include "needlesim/materials/hyperelastic.hpp"
#include "needlesim/materials/laws/law_unit.hpp"
#include "needlesim/scenario/schema.hpp"

using namespace needlesim;
using namespace needlesim::materials;

namespace {

// Keys of a material section that are not law parameters.
const std::set<std::string> kNotParameters{"base", "name", "law", "density", "prony"};

// One material per law, with every optional parameter set so that each term of
// the energy is exercised (Yeoh's C20 and C30, two Ogden terms of either sign).
const std::map<std::string, std::map<std::string, double>>& sampleParameters() {
  static const std::map<std::string, std::map<std::string, double>> m{
      {"linear", {{"E", 30e3}, {"nu", 0.42}}},
      {"neo-hookean", {{"C10", 3.6e3}, {"K", 80e3}}},
      {"mooney-rivlin", {{"C10", 2e3}, {"C01", 1.2e3}, {"nu", 0.45}}},
      {"yeoh", {{"C10", 2e3}, {"C20", 1.5e3}, {"C30", -400.0}, {"K", 60e3}}},
      {"ogden", {{"mu1", 4e3}, {"alpha1", 3.5}, {"mu2", -1e3}, {"alpha2", -2.0}, {"K", 90e3}}},
      {"fung", {{"mu", 5e3}, {"gamma", 1.8}, {"nu", 0.48}}},
  };
  return m;
}

Hyperelastic sampleLaw(const std::string& name) {
  const auto it = sampleParameters().find(name);
  if (it == sampleParameters().end()) throw std::runtime_error("no sample parameters for law " + name);
  MaterialSpec spec;
  spec.law = name;
  spec.params = it->second;
  return Hyperelastic::fromSpec(spec);
}

// d2/ds2 W(F(s)) at s = 0 by the central difference of step h (W(F(0)) = W(I) = 0).
template <class Path>
double secondDerivative(const Hyperelastic& law, Path F, double h) {
  return (strainEnergy(law, F(h)) - 2.0 * strainEnergy(law, F(0.0)) + strainEnergy(law, F(-h))) / (h * h);
}


}  // namespace

TEST(LawRegistry, LawsAreTheSchemasLaws) {
  std::vector<std::string> registered;
  for (const LawUnit* u : lawUnits()) registered.push_back(u->name);
  EXPECT_EQ(registered, scenario::field("material", "law").choices);
  EXPECT_EQ(registered, lawNames());
  // `needlesim schema` prints the same list on the material's law line.
  std::string joined;
  for (const auto& n : registered) joined += (joined.empty() ? "" : ", ") + n;
  std::istringstream text(scenario::schemaText());
  bool listed = false;
  for (std::string line; std::getline(text, line);)
    listed = listed || (line.find("law") != std::string::npos && line.find("one of: " + joined) != std::string::npos);
  EXPECT_TRUE(listed) << "no line of `needlesim schema` lists the laws " << joined;
  for (const LawUnit* u : lawUnits()) {
    EXPECT_EQ(&lawUnit(u->kind), u) << u->name;
    EXPECT_EQ(lawKind(u->name), u->kind);
    EXPECT_EQ(lawName(u->kind), u->name);
  }
}

TEST(LawRegistry, ParametersAreTheSchemasMaterialFields) {
  std::set<std::string> schemaKeys, lawKeys;
  for (const auto* f : scenario::fieldsOf("material"))
    if (!kNotParameters.count(f->key)) schemaKeys.insert(f->key);
  for (const LawUnit* u : lawUnits())
    for (const LawParam& p : lawParams(u->name)) {
      lawKeys.insert(p.key);
      // A key several laws take means the same quantity: same unit and range as the schema's.
      const scenario::FieldDoc& f = scenario::field("material", p.key);
      EXPECT_EQ(f.dim == units::dim::Pressure, p.pressure) << u->name << " " << p.key;
      EXPECT_EQ(f.lo, p.lo) << u->name << " " << p.key;
      EXPECT_EQ(f.hi, p.hi) << u->name << " " << p.key;
      EXPECT_EQ(f.lo_open, p.loOpen) << u->name << " " << p.key;
      EXPECT_EQ(f.hi_open, p.hiOpen) << u->name << " " << p.key;
    }
  EXPECT_EQ(schemaKeys, lawKeys);
}

TEST(LawRegistry, FittedParametersAreScenarioParameters) {
  for (const LawUnit* u : lawUnits()) {
    std::set<std::string> keys;
    for (const LawParam& p : lawParams(u->name)) keys.insert(p.key);
    for (int terms = 1; terms <= u->fit.maxTerms; ++terms)
      for (const FitStart& s : u->fit.starts(terms, 1e3)) {
        ASSERT_EQ(s.params.size(), s.values.size()) << u->name;
        for (const FitParamDef& d : s.params) EXPECT_TRUE(keys.count(d.name)) << u->name << " fits " << d.name;
      }
  }
}

namespace {

// mu0 = d2W/dgamma2 in simple shear F = I + gamma e1 e2^T, and K = d2W/de2 / 9 in
// the dilation F = (1 + e) I (W = 9 K e^2 / 2 + O(e^3) for every law). The central
// difference of step h = 1e-4 has a truncation error of h^2 W''''/12, below 1e-6
// of mu0 and K even for Ogden's alpha = 10; its round-off, about 1e-16 W(h) / h^2
// relative to W'' ~ 2 W(h) / h^2, is ~1e-8.
void expectModuliOfEnergy(const Hyperelastic& law, const std::string& label) {
  const double h = 1e-4;
  const auto shear = [](double g) {
    Mat3 F = Mat3::Identity();
    F(0, 1) = g;
    return F;
  };
  const auto dilation = [](double e) { return Mat3((1.0 + e) * Mat3::Identity()); };
  const double mu0 = law.initialShear(), K = law.initialBulk();
  EXPECT_NEAR(secondDerivative(law, shear, h), mu0, 1e-5 * mu0) << label;
  EXPECT_NEAR(secondDerivative(law, dilation, h) / 9.0, K, 1e-5 * K) << label;
  const Lame l = law.initialLame();
  EXPECT_NEAR(l.mu, mu0, 1e-12 * mu0) << label;
  EXPECT_NEAR(l.lambda + 2.0 / 3.0 * l.mu, K, 1e-9 * K) << label;
}

}  // namespace

TEST(LawRegistry, SmallStrainModuliAreTheEnergysSecondDerivatives) {
  for (const LawUnit* u : lawUnits()) {
    const Hyperelastic law = sampleLaw(u->name);
    expectModuliOfEnergy(law, u->name);
    MaterialSpec spec;
    spec.law = u->name;
    spec.params = sampleParameters().at(u->name);
    EXPECT_NEAR(smallStrainModuli(spec).shear, law.initialShear(), 1e-12 * law.initialShear()) << u->name;
    EXPECT_NEAR(smallStrainModuli(spec).bulk, law.initialBulk(), 1e-12 * law.initialBulk()) << u->name;
  }
}

// The same at every starting point of every law's fit (each term count), with K = 20 mu0.
TEST(LawRegistry, SmallStrainModuliAtEveryFitStart) {
  const double mu0 = 2e3;
  for (const LawUnit* u : lawUnits())
    for (int terms = 1; terms <= u->fit.maxTerms; ++terms)
      for (const FitStart& s : u->fit.starts(terms, mu0)) {
        Hyperelastic law;
        law.kind = u->kind;
        u->fit.fromFit(s.values, law);
        law.bulk = 20.0 * mu0;
        ASSERT_NO_THROW(law.validate()) << u->name;
        expectModuliOfEnergy(law, u->name + " (" + std::to_string(terms) + " terms)");
      }
}
