// The Fung-Demiray law (seed 000 eq 8): W = mu/(2 gamma) [exp(gamma (I1bar - 3)) - 1]
// + K/2 (J - 1)^2; dW/dI1bar = mu/2 at I1bar = 3, so the small-strain shear modulus is mu.
#include "needlesim/materials/laws/law_unit.hpp"

namespace needlesim::materials::laws {
namespace {

struct Fung {
  template <class T>
  static T energy(const Hyperelastic& m, const T& J, const T& I1, const T& I2, const T* h) {
    const auto iso = isochoric(m, J, I1, I2, h);
    return (m.mu / (2.0 * m.gamma)) * expm1(m.gamma * (iso.I1b - 3.0)) + volumetricEnergy(m, J);
  }
};

void read(const MaterialSpec& spec, Hyperelastic& h) {
  h.mu = spec.param("mu");
  h.gamma = spec.param("gamma");
}

void validate(const Hyperelastic& h) {
  requireFinite("fung", "mu", h.mu);
  requireFinite("fung", "gamma", h.gamma);
  if (!(h.mu > 0)) badParam("fung", "mu", h.mu, "mu must be > 0 Pa");
  if (!(h.gamma > 0)) badParam("fung", "gamma", h.gamma, "gamma must be > 0 (use neo-hookean for gamma = 0)");
}

std::vector<FitStart> fitStarts(int, double mu0) {
  const std::vector<FitParamDef> p{{"mu", "Pa", 1, mu0}, {"gamma", "1", 1, 1.0}};
  return {{p, {mu0, 0.1}}, {p, {mu0, 1.0}}, {p, {mu0, 5.0}}, {p, {0.3 * mu0, 10.0}}};
}

}  // namespace

const LawUnit& fungLaw() {
  static const LawUnit unit{
      .name = "fung",
      .kind = LawKind::Fung,
      .params = {positiveParam("mu", true, true, "Fung-Demiray modulus (seed 000 eq 8)"),
                 positiveParam("gamma", false, true, "Fung-Demiray exponent (seed 000 eq 8)")},
      .energy = energyOf<Fung>(),
      .read = read,
      .validate = validate,
      .shear = [](const Hyperelastic& h) { return h.mu; },
      .fit = {.starts = fitStarts,
              .fromFit =
                  [](const std::vector<double>& th, Hyperelastic& h) {
                    h.mu = th[0];
                    h.gamma = th[1];
                  }},
  };
  return unit;
}

}  // namespace needlesim::materials::laws
