#pragma once
// One constitutive law as one unit (materials/laws/<law>.cpp): its scenario
// name, its parameters (key, unit, range, help), how it reads them from a
// MaterialSpec and checks them, its strain energy, its small-strain moduli and
// what `needlesim fit` needs to fit it. Registered by one line of law_list.hpp.
// Internal to the materials and fit libraries (engines use hyperelastic.hpp).
#include <optional>
#include <string>
#include <tuple>
#include <vector>

#include "needlesim/materials/hyperelastic.hpp"
#include "needlesim/materials/second_order_ad.hpp"

namespace needlesim::materials {

// A parameter the least-squares fit varies: sign +1 (positive, fitted as its
// logarithm), -1 (negative, likewise) or 0 (free, fitted as value / scale).
struct FitParamDef {
  std::string name, unit;  // unit in SI: "Pa" or "1"
  int sign = 1;
  double scale = 1.0;  // typical magnitude
};

// One starting point of the fit: the parameters and their physical start values.
struct FitStart {
  std::vector<FitParamDef> params;
  std::vector<double> values;
};

// What `needlesim fit` needs of a law fitted to homogeneous test data.
struct LawFit {
  int defaultTerms = 1, maxTerms = 1;  // --terms: 0 means defaultTerms
  std::vector<int> rankedTerms{1};     // the term counts `--law auto` compares
  // true: compared with the small-strain incompressible response of Young's
  // modulus theta[0] (E = 3 mu0); false: with the exact incompressible response.
  bool smallStrain = false;
  std::vector<FitStart> (*starts)(int terms, double mu0) = nullptr;  // mu0: the data's initial shear modulus
  void (*fromFit)(const std::vector<double>& theta, Hyperelastic& h) = nullptr;
};

// W(J, I1, I2, h_1..h_3) evaluated with the automatic-differentiation scalars
// the library uses: Ad2<1> (homogeneous paths), Ad2<3> (invariants), Ad2<6>
// (invariants and the principal-stretch sums h_p = tr C^(alpha_p/2)).
template <class T>
using EnergyFn = T (*)(const Hyperelastic&, const T& J, const T& I1, const T& I2, const T* h);
using LawEnergy = std::tuple<EnergyFn<detail::Ad2<1>>, EnergyFn<detail::Ad2<3>>, EnergyFn<detail::Ad2<6>>>;

// Law::energy<T> of a law unit's energy structure, for every scalar type.
template <class Law>
constexpr LawEnergy energyOf() {
  return {&Law::template energy<detail::Ad2<1>>, &Law::template energy<detail::Ad2<3>>,
          &Law::template energy<detail::Ad2<6>>};
}

struct LawUnit {
  std::string name;  // scenario name
  LawKind kind;
  // The law's own parameters; a law with `volumetric` also takes K or nu (volumetricParams()).
  std::vector<LawParam> params;
  LawEnergy energy;
  void (*read)(const MaterialSpec&, Hyperelastic&);  // the own parameters into the law
  void (*validate)(const Hyperelastic&);             // throws Error naming the parameter
  // Small-strain shear modulus mu0 = d2W/dgamma2 at F = I (simple shear gamma).
  double (*shear)(const Hyperelastic&);
  LawFit fit;
  // true: W = W_iso(I1bar, I2bar, hbar) + K/2 (J - 1)^2 with K given or from nu, and
  // the small-strain bulk modulus is K; false: `energy` is the whole W, and bulk and
  // lame give its small-strain moduli.
  bool volumetric = true;
  double (*bulk)(const Hyperelastic&) = nullptr;
  Lame (*lame)(const Hyperelastic&) = nullptr;
  bool stretches = false;  // the energy uses h_p of the exponents ogdenAlpha
  std::optional<ParamProblem> (*check)(const MaterialSpec&) = nullptr;  // rules between parameters
};

const std::vector<const LawUnit*>& lawUnits();
const LawUnit& lawUnit(LawKind kind);
const LawUnit* findLawUnit(const std::string& name);  // nullptr for an unknown name
const LawUnit& lawUnit(const std::string& name);      // throws Error naming the laws
// The parameters of the volumetric part U(J): K or nu (neither required).
const std::vector<LawParam>& volumetricParams();
// The small-strain moduli of a law whose parameters are set.
SmallStrainModuli smallStrainModuli(const Hyperelastic& h);

namespace laws {

#define NEEDLESIM_DECLARE_LAW(kind, fn) const LawUnit& fn();
NEEDLESIM_LAWS(NEEDLESIM_DECLARE_LAW)
#undef NEEDLESIM_DECLARE_LAW

// Ranges the laws' parameters declare.
LawParam positiveParam(std::string key, bool pressure, bool required, std::string help);
LawParam nonNegativeParam(std::string key, bool pressure, bool required, std::string help);
LawParam anyParam(std::string key, bool pressure, bool required, std::string help);
// C10, the coefficient of (I1bar - 3) that the invariant laws share.
LawParam c10Param();

// Throws Error: "material law '<law>': parameter <key> = <v> is not allowed; <allowed>".
[[noreturn]] void badParam(const std::string& law, const std::string& key, double v, const std::string& allowed);
void requireFinite(const std::string& law, const std::string& key, double v);
std::string numberText(double v);

// Isochoric invariants I1bar = J^(-2/3) I1, I2bar = J^(-4/3) I2, hbar_p = J^(-alpha_p/3) h_p.
template <class T>
struct Isochoric {
  T I1b, I2b;
  T hb[3];
};
template <class T>
Isochoric<T> isochoric(const Hyperelastic& m, const T& J, const T& I1, const T& I2, const T* h) {
  Isochoric<T> r{pow(J, -2.0 / 3.0) * I1, pow(J, -4.0 / 3.0) * I2, {T(0.0), T(0.0), T(0.0)}};
  for (std::size_t p = 0; p < m.ogdenAlpha.size() && p < 3; ++p) r.hb[p] = pow(J, -m.ogdenAlpha[p] / 3.0) * h[p];
  return r;
}

// U(J) = K/2 (J - 1)^2 (the ABAQUS form, D1 = 2/K).
template <class T>
T volumetricEnergy(const Hyperelastic& m, const T& J) {
  T Jm1 = J - 1.0;
  return (0.5 * m.bulk) * (Jm1 * Jm1);
}

}  // namespace laws
}  // namespace needlesim::materials
