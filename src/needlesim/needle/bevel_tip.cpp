#include "needlesim/needle/bevel_tip.hpp"

#include <cmath>
#include <numbers>
#include <stdexcept>

namespace needlesim::needle {

TipLoads bevelTipLoads(const TipLoadInput& in) {
  if (!(in.alpha > 0 && in.alpha < std::numbers::pi / 2))
    throw std::invalid_argument("bevel angle must lie in (0, 90) deg");
  if (!(in.beta >= 0 && in.beta <= in.alpha))
    throw std::invalid_argument("cut angle beta must lie in [0, alpha]");
  if (!(in.diameter > 0) || !(in.K_T >= 0))
    throw std::invalid_argument("tip loads need d > 0 and K_T >= 0");
  TipLoads t;
  const double d = in.diameter, al = in.alpha, be = in.beta;
  const double sa = std::sin(al), ca = std::cos(al), tb = std::tan(be);
  // Fig 13 geometry: alpha = gamma + beta, a = d/tan(alpha), b = d/sin(alpha),
  // e = d - a tan(beta) - (b/3) sin(alpha)  (the extracted text prints "alpha tan beta";
  // the lever arm is a length, so it is a tan(beta), as in eq 20).
  t.gamma = al - be;
  t.a = d / std::tan(al);
  t.b = d / sa;
  t.e = d - t.a * tb - t.b / 3.0 * sa;
  // (tan(alpha) - tan(beta)) / (1 + tan(alpha) tan(beta)) = tan(gamma)
  const double tg = std::tan(t.gamma);
  t.F1 = in.K_T * t.a * t.a / 2.0 * tb;  // eq 22
  t.F2 = in.K_T * t.b * t.b / 2.0 * tg;  // eq 23
  t.P = in.P_input - t.F2 * sa;          // eq 24
  t.Q = t.F1 - t.F2 * ca;                // eq 25
  t.M = t.F2 * (t.b / 3.0 * ca * ca - t.e * sa) - in.K_T * t.a * t.a * t.a / 6.0 * tb;  // eq 26
  return t;
}

}  // namespace needlesim::needle
