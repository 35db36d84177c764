// Four material points at a time: the decoupled Fung-Demiray and neo-Hookean
// Cauchy stresses of the MPM stress update (seed 000 eqs 8-13; the same laws
// as law_energy.hpp) on GCC vector lanes, so the exp, square root, division
// and J^(-1/3) chains of four points overlap. The lane functions are always
// inlined, so they take the instruction set of the kernel clone that calls
// them (mpm/mpm_solver.cpp). Checked against the library's energy and stress
// and lane by lane (tests/materials, StressLanes.*).
#pragma once

#include <cmath>
#include <cstdint>
#include <cstring>

#include "needlesim/materials/hyperelastic.hpp"

namespace needlesim::materials::lanes {

#pragma GCC diagnostic ignored "-Wpsabi"  // lane helpers are inlined into each clone
typedef double A4 __attribute__((vector_size(32), aligned(8), may_alias));
typedef long long I4 __attribute__((vector_size(32), aligned(8), may_alias));

// J^(-1/3) for J > 0 without pow or a division. Near J = 1 (soft tissue is
// nearly incompressible): the Taylor series 1 - e/3 + 2e^2/9 in e = J - 1 (error
// 14|e|^3/81 < 2.2e-5 for |e| < 0.05), then two Newton steps
// z <- z (4 - J z^3) / 3 (quadratic: to rounding). Elsewhere: an exponent-bit
// estimate (within 3.5 %), then four Newton steps.
inline double invCbrt(double J) {
  const double e = J - 1.0;
  double z;
  int steps;
  if (std::abs(e) < 0.05) {
    z = 1.0 + e * (-1.0 / 3.0 + e * (2.0 / 9.0));
    steps = 2;
  } else {
    std::uint64_t i;
    std::memcpy(&i, &J, sizeof i);
    i = 0x553ef0ff289dd796ull - i / 3;  // (4/3) x bias bits - bits/3, tuned constant
    std::memcpy(&z, &i, sizeof z);
    steps = 4;
  }
  for (int it = 0; it < steps; ++it) z *= (4.0 - J * z * z * z) * (1.0 / 3.0);
  return z;
}

// invCbrt on four lanes: the Taylor branch when every lane is near 1, else lane by lane.
[[gnu::always_inline]] inline A4 invCbrt4(A4 J) {
  const A4 e = J - 1.0;
  bool near = true;
  for (int l = 0; l < 4; ++l) near = near && std::abs(e[l]) < 0.05;
  if (!near) return A4{invCbrt(J[0]), invCbrt(J[1]), invCbrt(J[2]), invCbrt(J[3])};
  A4 z = 1.0 + e * (-1.0 / 3.0 + e * (2.0 / 9.0));
  for (int it = 0; it < 2; ++it) z *= (4.0 - J * z * z * z) * (1.0 / 3.0);
  return z;
}

// exp on four lanes, for |x| <= 700 (the caller takes other lanes to
// std::exp): x = n ln 2 + r with |r| <= ln 2 / 2 (Cody-Waite split of ln 2, so
// n ln2_hi is exact), e^r by its Taylor series to r^13 (truncation < 4e-18
// relative), 2^n from the exponent bits. n is rounded by adding 1.5 x 2^52,
// which leaves it in the low bits of the mantissa.
[[gnu::always_inline]] inline A4 exp4(A4 x) {
  constexpr double shifter = 6755399441055744.0;  // 1.5 x 2^52
  constexpr double ln2hi = 6.93147180369123816490e-01, ln2lo = 1.90821492927058770002e-10;
  const A4 t = x * 1.4426950408889634 + shifter;
  const A4 n = t - shifter;
  const A4 r = (x - n * ln2hi) - n * ln2lo;
  A4 p = r * (1.0 / 6227020800.0) + 1.0 / 479001600.0;  // 1/13!, 1/12!
  p = p * r + 1.0 / 39916800.0;
  p = p * r + 1.0 / 3628800.0;
  p = p * r + 1.0 / 362880.0;
  p = p * r + 1.0 / 40320.0;
  p = p * r + 1.0 / 5040.0;
  p = p * r + 1.0 / 720.0;
  p = p * r + 1.0 / 120.0;
  p = p * r + 1.0 / 24.0;
  p = p * r + 1.0 / 6.0;
  p = p * r + 0.5;
  p = p * r + 1.0;
  p = p * r + 1.0;
  const A4 sh = A4{} + shifter;
  const I4 scale = (reinterpret_cast<const I4&>(t) - reinterpret_cast<const I4&>(sh) + 1023) << 52;
  return p * reinterpret_cast<const A4&>(scale);
}

// Cauchy stress (Voigt 11 22 33 12 23 13), energy per reference volume W and
// the dilatational wave speed sqrt((K + 4/3 mu_t) / rho) (seed 000 eq 27, mu_t
// the current tangent shear modulus, rho = rho0 / J) of four points of one
// Fung-Demiray or neo-Hookean law L, from the rows of F (F[3 r + c] = F_rc,
// lane = point); rho0 the reference density (MPM: times the mass scaling).
[[gnu::always_inline]] inline void hyperelasticStress4(const Hyperelastic& L, double rho0, const A4 (&F)[9],
                                                       A4 (&sig)[6], A4& W, A4& wave) {
  const A4 J = F[0] * (F[4] * F[8] - F[5] * F[7]) - F[1] * (F[3] * F[8] - F[5] * F[6]) +
               F[2] * (F[3] * F[7] - F[4] * F[6]);
  const A4 b00 = F[0] * F[0] + F[1] * F[1] + F[2] * F[2], b11 = F[3] * F[3] + F[4] * F[4] + F[5] * F[5],
           b22 = F[6] * F[6] + F[7] * F[7] + F[8] * F[8], b01 = F[0] * F[3] + F[1] * F[4] + F[2] * F[5],
           b12 = F[3] * F[6] + F[4] * F[7] + F[5] * F[8], b02 = F[0] * F[6] + F[1] * F[7] + F[2] * F[8];
  const A4 Jm13 = invCbrt4(J);
  const A4 Jm23 = Jm13 * Jm13;
  const A4 trb = b00 + b11 + b22;
  const A4 I1b = Jm23 * trb;
  A4 W1, muc;
  if (L.kind == LawKind::Fung) {
    const A4 x = L.gamma * (I1b - 3.0);
    bool inRange = true;
    for (int l = 0; l < 4; ++l) inRange = inRange && std::abs(x[l]) <= 700.0;
    const A4 ex = inRange ? exp4(x) : A4{std::exp(x[0]), std::exp(x[1]), std::exp(x[2]), std::exp(x[3])};
    W1 = 0.5 * L.mu * ex;
    // expm1 from ex: a short series where ex - 1 would cancel.
    const A4 series = x * (1.0 + x * (0.5 + x * (1.0 / 6.0 + x / 24.0)));
    const A4 absx = x < 0.0 ? -x : x;
    const A4 em1 = absx < 1e-3 ? series : ex - 1.0;
    W = L.mu / (2.0 * L.gamma) * em1;
    muc = L.mu * ex * (1.0 + 2.0 * L.gamma * I1b);
  } else {  // neo-Hookean
    W1 = A4{} + L.C10;
    W = L.C10 * (I1b - 3.0);
    muc = A4{} + 2.0 * L.C10;
  }
  const double K = L.bulk;
  W += 0.5 * K * (J - 1.0) * (J - 1.0);
  const A4 c = 2.0 * W1 * Jm23 / J;
  const A4 diag = -c * trb / 3.0 + K * (J - 1.0);
  sig[0] = c * b00 + diag;
  sig[1] = c * b11 + diag;
  sig[2] = c * b22 + diag;
  sig[3] = c * b01;
  sig[4] = c * b12;
  sig[5] = c * b02;
  const A4 rho = rho0 / J;
  const A4 w2 = (K + 4.0 / 3.0 * muc) / rho;
  wave = A4{std::sqrt(w2[0]), std::sqrt(w2[1]), std::sqrt(w2[2]), std::sqrt(w2[3])};
}

// Whether a law takes the lane path.
inline bool hasLanes(const Hyperelastic& L) { return L.kind == LawKind::Fung || L.kind == LawKind::NeoHookean; }

}  // namespace needlesim::materials::lanes
