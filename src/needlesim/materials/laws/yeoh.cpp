// The Yeoh law: W = C10 x + C20 x^2 + C30 x^3 + K/2 (J - 1)^2 with x = I1bar - 3,
// small-strain shear modulus mu0 = 2 C10.
#include "needlesim/materials/laws/law_unit.hpp"

namespace needlesim::materials::laws {
namespace {

struct Yeoh {
  template <class T>
  static T energy(const Hyperelastic& m, const T& J, const T& I1, const T& I2, const T* h) {
    const auto iso = isochoric(m, J, I1, I2, h);
    T x = iso.I1b - 3.0;
    return m.C10 * x + m.C20 * (x * x) + m.C30 * (x * x * x) + volumetricEnergy(m, J);
  }
};

void read(const MaterialSpec& spec, Hyperelastic& h) {
  h.C10 = spec.param("C10");
  h.C20 = spec.paramOr("C20", 0.0);
  h.C30 = spec.paramOr("C30", 0.0);
}

void validate(const Hyperelastic& h) {
  requireFinite("yeoh", "C10", h.C10);
  requireFinite("yeoh", "C20", h.C20);
  requireFinite("yeoh", "C30", h.C30);
  if (!(h.C10 > 0)) badParam("yeoh", "C10", h.C10, "C10 must be > 0 Pa");
}

// Terms 1-3: C10 (positive), then C20, C30 (either sign).
std::vector<FitStart> fitStarts(int terms, double mu0) {
  const char* nm[3] = {"C10", "C20", "C30"};
  std::vector<FitParamDef> p;
  for (int i = 0; i < terms; ++i) p.push_back({nm[i], "Pa", i == 0 ? 1 : 0, mu0});
  std::vector<double> s0(terms, 0.0), s1(terms, 0.0);
  s0[0] = s1[0] = mu0 / 2;
  if (terms > 1) s1[1] = 0.1 * mu0;
  return {{p, s0}, {p, s1}};
}

void fromFit(const std::vector<double>& th, Hyperelastic& h) {
  h.C10 = th[0];
  h.C20 = th.size() > 1 ? th[1] : 0.0;
  h.C30 = th.size() > 2 ? th[2] : 0.0;
}

}  // namespace

const LawUnit& yeohLaw() {
  static const LawUnit unit{
      .name = "yeoh",
      .kind = LawKind::Yeoh,
      .params = {c10Param(), anyParam("C20", true, false, "Yeoh second coefficient"),
                 anyParam("C30", true, false, "Yeoh third coefficient")},
      .energy = energyOf<Yeoh>(),
      .read = read,
      .validate = validate,
      .shear = [](const Hyperelastic& h) { return 2.0 * h.C10; },
      .fit = {.defaultTerms = 3, .maxTerms = 3, .rankedTerms = {2, 3}, .starts = fitStarts, .fromFit = fromFit},
  };
  return unit;
}

}  // namespace needlesim::materials::laws
