#pragma once
// The strain energy of every law as one templated scalar formula in the
// invariants (J, I1, I2, h_p = tr C^(alpha_p/2)); internal to the materials
// library. Instantiated with double, or with detail::Ad2 for exact first and
// second derivatives (stress and tangent). See docs/models/materials.md.
#include <cmath>

#include "needlesim/materials/hyperelastic.hpp"
#include "needlesim/materials/second_order_ad.hpp"

namespace needlesim::materials::detail {

using std::exp;
using std::expm1;
using std::pow;

// Isochoric part from isochoric invariants I1b, I2b and hb[p] = sum_a lambda_bar_a^alpha_p.
template <class T>
T isochoricEnergy(const Hyperelastic& m, const T& I1b, const T& I2b, const T* hb) {
  switch (m.kind) {
    case LawKind::NeoHookean:  // seed 002 eq 7: W = C10 (I1 - 3)
      return m.C10 * (I1b - 3.0);
    case LawKind::MooneyRivlin:
      return m.C10 * (I1b - 3.0) + m.C01 * (I2b - 3.0);
    case LawKind::Yeoh: {
      T x = I1b - 3.0;
      return m.C10 * x + m.C20 * (x * x) + m.C30 * (x * x * x);
    }
    case LawKind::Ogden: {
      T w(0.0);
      for (std::size_t p = 0; p < m.ogdenMu.size(); ++p)
        w = w + (m.ogdenMu[p] / m.ogdenAlpha[p]) * (hb[p] - 3.0);
      return w;
    }
    case LawKind::Fung:  // seed 000 eq 8: W = mu/(2 gamma) [exp(gamma (I1 - 3)) - 1]
      return (m.mu / (2.0 * m.gamma)) * expm1(m.gamma * (I1b - 3.0));
    case LawKind::Linear:
      break;
  }
  return T(0.0);
}

// Full energy from (J, I1, I2, h[p] = tr C^(alpha_p/2)) of C = F^T F.
template <class T>
T totalEnergy(const Hyperelastic& m, const T& J, const T& I1, const T& I2, const T* h) {
  if (m.kind == LawKind::Linear) {
    // St Venant-Kirchhoff: W = lambda/2 (tr E)^2 + mu E:E, E = (C - I)/2; equals
    // linear elasticity at small strain.
    const auto [lam, mu] = lame(m.E, m.nu);
    T trE = 0.5 * (I1 - 3.0);
    T EE = 0.25 * (I1 * I1 - 2.0 * I2 - 2.0 * I1 + 3.0);
    return 0.5 * lam * (trE * trE) + mu * EE;
  }
  T I1b = pow(J, -2.0 / 3.0) * I1;
  T I2b = pow(J, -4.0 / 3.0) * I2;
  T hb[3] = {T(0.0), T(0.0), T(0.0)};
  for (std::size_t p = 0; p < m.ogdenAlpha.size() && p < 3; ++p)
    hb[p] = pow(J, -m.ogdenAlpha[p] / 3.0) * h[p];
  T Jm1 = J - 1.0;
  return isochoricEnergy(m, I1b, I2b, hb) + (0.5 * m.bulk) * (Jm1 * Jm1);
}

}  // namespace needlesim::materials::detail
