// The Ogden law: W = sum_p mu_p / alpha_p (lbar_1^a_p + lbar_2^a_p + lbar_3^a_p - 3)
// + K/2 (J - 1)^2 in the isochoric principal stretches, 1 to 3 terms; the
// small-strain shear modulus is mu0 = sum_p mu_p alpha_p / 2.
#include "needlesim/core/error.hpp"
#include "needlesim/materials/laws/law_unit.hpp"

namespace needlesim::materials::laws {
namespace {

struct Ogden {
  template <class T>
  static T energy(const Hyperelastic& m, const T& J, const T& I1, const T& I2, const T* h) {
    const auto iso = isochoric(m, J, I1, I2, h);
    T w(0.0);
    for (std::size_t p = 0; p < m.ogdenMu.size(); ++p) w = w + (m.ogdenMu[p] / m.ogdenAlpha[p]) * (iso.hb[p] - 3.0);
    return w + volumetricEnergy(m, J);
  }
};

std::vector<LawParam> params() {
  std::vector<LawParam> v;
  for (int i = 1; i <= 3; ++i) {
    const std::string k = std::to_string(i);
    v.push_back(anyParam("mu" + k, true, i == 1, "Ogden modulus of term " + k));
    v.push_back(anyParam("alpha" + k, false, i == 1, "Ogden exponent of term " + k));
  }
  return v;
}

void read(const MaterialSpec& spec, Hyperelastic& h) {
  for (int p = 1; p <= 3; ++p) {
    std::string k = std::to_string(p);
    if (!spec.has("mu" + k) && !spec.has("alpha" + k)) continue;
    h.ogdenMu.push_back(spec.param("mu" + k));
    h.ogdenAlpha.push_back(spec.param("alpha" + k));
  }
}

// A term needs both mu_p and alpha_p, and alpha_p != 0.
std::optional<ParamProblem> check(const MaterialSpec& spec) {
  for (int i = 1; i <= 3; ++i) {
    const std::string k = std::to_string(i);
    const bool hasMu = spec.has("mu" + k), hasAlpha = spec.has("alpha" + k);
    if (hasMu != hasAlpha)
      return ParamProblem{(hasMu ? "alpha" : "mu") + k, "", "Ogden terms need both mu and alpha",
                          "mu" + k + " and alpha" + k};
    if (hasAlpha && spec.param("alpha" + k) == 0.0)
      return ParamProblem{"alpha" + k, "0", "an Ogden exponent must be non-zero", "alpha != 0"};
  }
  return std::nullopt;
}

void validate(const Hyperelastic& h) {
  if (h.ogdenMu.empty() || h.ogdenMu.size() != h.ogdenAlpha.size() || h.ogdenMu.size() > 3)
    throw Error("material law 'ogden' needs 1 to 3 pairs (mu_p, alpha_p); got " + std::to_string(h.ogdenMu.size()) +
                " mu and " + std::to_string(h.ogdenAlpha.size()) + " alpha");
  for (std::size_t p = 0; p < h.ogdenMu.size(); ++p) {
    std::string k = std::to_string(p + 1);
    requireFinite("ogden", "mu" + k, h.ogdenMu[p]);
    requireFinite("ogden", "alpha" + k, h.ogdenAlpha[p]);
    if (h.ogdenAlpha[p] == 0.0) badParam("ogden", "alpha" + k, 0.0, "alpha_p must be non-zero");
    if (!(h.ogdenMu[p] * h.ogdenAlpha[p] > 0))
      badParam("ogden", "mu" + k, h.ogdenMu[p],
               "mu_p alpha_p must be > 0 (stability); alpha" + k + " = " + numberText(h.ogdenAlpha[p]));
  }
}

double shear(const Hyperelastic& h) {
  double s = 0.0;
  for (std::size_t p = 0; p < h.ogdenMu.size(); ++p) s += 0.5 * h.ogdenMu[p] * h.ogdenAlpha[p];
  return s;
}

// Sign patterns and exponents; each term carries mu0/terms, and mu_p alpha_p > 0
// by construction (mu_p and alpha_p share their sign).
std::vector<FitStart> fitStarts(int terms, double mu0) {
  std::vector<std::vector<double>> alphaSets;
  if (terms == 1) alphaSets = {{2.0}, {5.0}, {10.0}, {-2.0}, {-6.0}};
  if (terms == 2) alphaSets = {{2.0, -2.0}, {6.0, -2.0}, {2.0, 8.0}, {10.0, -4.0}, {1.5, 5.0}};
  if (terms == 3) alphaSets = {{2.0, -2.0, 6.0}, {1.0, 4.0, -2.0}, {8.0, -4.0, 2.0}, {2.0, 5.0, 10.0}};
  std::vector<FitStart> starts;
  for (const auto& alphas : alphaSets) {
    FitStart s;
    for (std::size_t t = 0; t < alphas.size(); ++t) {
      const double a = alphas[t];
      const int sgn = a > 0 ? 1 : -1;
      s.params.push_back({"mu" + std::to_string(t + 1), "Pa", sgn, mu0});
      s.params.push_back({"alpha" + std::to_string(t + 1), "1", sgn, 1.0});
      s.values.push_back(2.0 * mu0 / (a * terms));
      s.values.push_back(a);
    }
    starts.push_back(s);
  }
  return starts;
}

void fromFit(const std::vector<double>& th, Hyperelastic& h) {
  for (std::size_t i = 0; i + 1 < th.size(); i += 2) {
    h.ogdenMu.push_back(th[i]);
    h.ogdenAlpha.push_back(th[i + 1]);
  }
}

}  // namespace

const LawUnit& ogdenLaw() {
  static const LawUnit unit{
      .name = "ogden",
      .kind = LawKind::Ogden,
      .params = params(),
      .energy = energyOf<Ogden>(),
      .read = read,
      .validate = validate,
      .shear = shear,
      .fit = {.defaultTerms = 1, .maxTerms = 3, .rankedTerms = {1, 2}, .starts = fitStarts, .fromFit = fromFit},
      .stretches = true,
      .check = check,
  };
  return unit;
}

}  // namespace needlesim::materials::laws
