// The neo-Hookean law (seed 002 eq 7, seed 004 eq 7):
// W = C10 (I1bar - 3) + K/2 (J - 1)^2, small-strain shear modulus mu0 = 2 C10.
#include "needlesim/materials/laws/law_unit.hpp"

namespace needlesim::materials::laws {
namespace {

struct NeoHookean {
  template <class T>
  static T energy(const Hyperelastic& m, const T& J, const T& I1, const T& I2, const T* h) {
    const auto iso = isochoric(m, J, I1, I2, h);
    return m.C10 * (iso.I1b - 3.0) + volumetricEnergy(m, J);
  }
};

void validate(const Hyperelastic& h) {
  requireFinite("neo-hookean", "C10", h.C10);
  if (!(h.C10 > 0)) badParam("neo-hookean", "C10", h.C10, "C10 must be > 0 Pa");
}

std::vector<FitStart> fitStarts(int, double mu0) { return {{{{"C10", "Pa", 1, mu0}}, {mu0 / 2}}}; }

}  // namespace

const LawUnit& neoHookeanLaw() {
  static const LawUnit unit{
      .name = "neo-hookean",
      .kind = LawKind::NeoHookean,
      .params = {c10Param()},
      .energy = energyOf<NeoHookean>(),
      .read = [](const MaterialSpec& spec, Hyperelastic& h) { h.C10 = spec.param("C10"); },
      .validate = validate,
      .shear = [](const Hyperelastic& h) { return 2.0 * h.C10; },
      .fit = {.starts = fitStarts,
              .fromFit = [](const std::vector<double>& th, Hyperelastic& h) { h.C10 = th[0]; }},
  };
  return unit;
}

}  // namespace needlesim::materials::laws
