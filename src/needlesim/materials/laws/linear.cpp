// The "linear" law: St Venant-Kirchhoff at finite strain, W = lambda/2 (tr E)^2
// + mu E:E with E = (C - I)/2 and the Lame constants of E and nu (seed 003 eqs
// 3.10-3.11); it equals linear elasticity at small strain. No volumetric split.
#include "needlesim/materials/laws/law_unit.hpp"

namespace needlesim::materials::laws {
namespace {

struct Linear {
  template <class T>
  static T energy(const Hyperelastic& m, const T&, const T& I1, const T& I2, const T*) {
    const auto [lam, mu] = lame(m.E, m.nu);
    T trE = 0.5 * (I1 - 3.0);
    T EE = 0.25 * (I1 * I1 - 2.0 * I2 - 2.0 * I1 + 3.0);
    return 0.5 * lam * (trE * trE) + mu * EE;
  }
};

void read(const MaterialSpec& spec, Hyperelastic& h) {
  h.E = spec.param("E");
  h.nu = spec.param("nu");
}

void validate(const Hyperelastic& h) {
  requireFinite("linear", "E", h.E);
  requireFinite("linear", "nu", h.nu);
  if (!(h.E > 0)) badParam("linear", "E", h.E, "E must be > 0 Pa");
  if (!(h.nu > -1.0 && h.nu < 0.5)) badParam("linear", "nu", h.nu, "-1 < nu < 0.5");
}

// Fitted as sigma = E eps (uniaxial), 2 E eps (equibiaxial), E/3 gamma (shear), from E = 3 mu0.
std::vector<FitStart> fitStarts(int, double mu0) {
  const double E0 = 3.0 * mu0;
  return {{{{"E", "Pa", 1, E0}}, {E0}}};
}

}  // namespace

const LawUnit& linearLaw() {
  static const LawUnit unit{
      .name = "linear",
      .kind = LawKind::Linear,
      .params = {positiveParam("E", true, true, "Young's modulus (linear)"),
                 {"nu", false, true, "Poisson ratio (linear; or the volumetric part of a hyperelastic law)", -1.0,
                  0.5, true, true}},
      .energy = energyOf<Linear>(),
      .read = read,
      .validate = validate,
      .shear = [](const Hyperelastic& h) { return lame(h.E, h.nu).mu; },
      .fit = {.smallStrain = true,
              .starts = fitStarts,
              .fromFit = [](const std::vector<double>& th, Hyperelastic& h) { h.E = th[0]; }},
      .volumetric = false,
      .bulk = [](const Hyperelastic& h) { return bulkModulus(h.E, h.nu); },
      .lame = [](const Hyperelastic& h) { return lame(h.E, h.nu); },
  };
  return unit;
}

}  // namespace needlesim::materials::laws
