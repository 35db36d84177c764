// The Mooney-Rivlin law: W = C10 (I1bar - 3) + C01 (I2bar - 3) + K/2 (J - 1)^2,
// small-strain shear modulus mu0 = 2 (C10 + C01).
#include "needlesim/materials/laws/law_unit.hpp"

namespace needlesim::materials::laws {
namespace {

struct MooneyRivlin {
  template <class T>
  static T energy(const Hyperelastic& m, const T& J, const T& I1, const T& I2, const T* h) {
    const auto iso = isochoric(m, J, I1, I2, h);
    return m.C10 * (iso.I1b - 3.0) + m.C01 * (iso.I2b - 3.0) + volumetricEnergy(m, J);
  }
};

void read(const MaterialSpec& spec, Hyperelastic& h) {
  h.C10 = spec.param("C10");
  h.C01 = spec.param("C01");
}

void validate(const Hyperelastic& h) {
  requireFinite("mooney-rivlin", "C10", h.C10);
  requireFinite("mooney-rivlin", "C01", h.C01);
  if (!(h.C10 + h.C01 > 0))
    badParam("mooney-rivlin", "C10 + C01", h.C10 + h.C01, "the initial shear modulus 2 (C10 + C01) must be > 0");
}

std::vector<FitStart> fitStarts(int, double mu0) {
  const std::vector<FitParamDef> p{{"C10", "Pa", 1, mu0}, {"C01", "Pa", 1, mu0}};
  return {{p, {mu0 / 4, mu0 / 4}}, {p, {0.45 * mu0, 0.05 * mu0}}, {p, {0.05 * mu0, 0.45 * mu0}}};
}

}  // namespace

const LawUnit& mooneyRivlinLaw() {
  static const LawUnit unit{
      .name = "mooney-rivlin",
      .kind = LawKind::MooneyRivlin,
      .params = {c10Param(), nonNegativeParam("C01", true, true, "Mooney-Rivlin second coefficient")},
      .energy = energyOf<MooneyRivlin>(),
      .read = read,
      .validate = validate,
      .shear = [](const Hyperelastic& h) { return 2.0 * (h.C10 + h.C01); },
      .fit = {.starts = fitStarts,
              .fromFit =
                  [](const std::vector<double>& th, Hyperelastic& h) {
                    h.C10 = th[0];
                    h.C01 = th[1];
                  }},
  };
  return unit;
}

}  // namespace needlesim::materials::laws
