#include "needlesim/materials/viscoelastic.hpp"

#include "needlesim/core/error.hpp"

namespace needlesim::materials {

double Prony::gInfinity() const {
  double s = 1.0;
  for (const auto& t : terms) s -= t.g;
  return s;
}

double Prony::relaxation(double t) const {
  double G = gInfinity();
  for (const auto& term : terms) G += term.g * std::exp(-t / term.tau);
  return G;
}

double Prony::stepFactor(double dt) const {
  double f = gInfinity();
  for (const auto& term : terms) f += term.g * phi1(dt / term.tau);
  return f;
}

void Prony::validate() const {
  double sum = 0.0;
  for (std::size_t i = 0; i < terms.size(); ++i) {
    const auto& t = terms[i];
    const std::string k = "prony term " + std::to_string(i + 1);
    if (!std::isfinite(t.g) || t.g < 0.0 || t.g >= 1.0)
      throw Error(k + ": g = " + std::to_string(t.g) + " is not allowed; 0 <= g < 1");
    if (!std::isfinite(t.tau) || !(t.tau > 0.0))
      throw Error(k + ": tau = " + std::to_string(t.tau) + " s is not allowed; tau > 0 s");
    sum += t.g;
  }
  if (sum >= 1.0)
    throw Error("prony series: sum of g_i = " + std::to_string(sum) +
                " is not allowed; it must be < 1 (the long-term modulus g_inf = 1 - sum g_i must stay positive)");
}

}  // namespace needlesim::materials
