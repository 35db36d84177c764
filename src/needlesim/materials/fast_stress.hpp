#pragma once
// Closed-form stresses of the engines' hot loops (explicit FE element loop,
// MPM stress update): the neo-Hookean and St Venant-Kirchhoff ("linear")
// second Piola-Kirchhoff stress and energy, inline, without the automatic
// differentiation of materials::evaluate (always inlined: into the caller's
// loop and, in the MPM, its instruction-set clone). The same laws as law_energy.hpp;
// tests/materials (FastStress.*) checks them against the library's energy
// and stress at random deformation gradients. For the Fung-Demiray and
// neo-Hookean Cauchy stress of four points on vector lanes see stress_lanes.hpp.
#include <Eigen/Core>
#include <Eigen/LU>
#include <cmath>

#include "needlesim/materials/elastic_moduli.hpp"
#include "needlesim/materials/hyperelastic.hpp"

namespace needlesim::materials {

// Neo-Hooke with the volumetric part (seed 002 eq 7, U = K/2 (J - 1)^2):
//   W = C10 (I1bar - 3) + K/2 (J - 1)^2,
//   S = 2 C10 J^(-2/3) (I - I1/3 C^-1) + K (J - 1) J C^-1,
// J = det F > 0 from the caller.
[[gnu::always_inline]] inline void neoHookeanPk2(double C10, double K, const Mat3& F, double J, Mat3& S, double& W) {
  const Mat3 C = F.transpose() * F;
  const Mat3 Ci = C.inverse();
  const double I1 = C.trace(), Jm23 = std::cbrt(1.0 / (J * J));
  S = 2.0 * C10 * Jm23 * (Mat3::Identity() - (I1 / 3.0) * Ci) + K * (J - 1.0) * J * Ci;
  W = C10 * (Jm23 * I1 - 3.0) + 0.5 * K * (J - 1.0) * (J - 1.0);
}

// St Venant-Kirchhoff, the library's "linear" law at finite strain:
//   W = lambda/2 (tr E)^2 + mu E:E,  S = lambda tr(E) I + 2 mu E,  E = (F^T F - I)/2.
[[gnu::always_inline]] inline void stVenantKirchhoffPk2(const Lame& l, const Mat3& F, Mat3& S, double& W) {
  const Mat3 E = 0.5 * (F.transpose() * F - Mat3::Identity());
  const double tr = E.trace();
  S = l.lambda * tr * Mat3::Identity() + 2 * l.mu * E;
  W = 0.5 * l.lambda * tr * tr + l.mu * (E.array() * E.array()).sum();
}

// S and W of any law at F (J = det F > 0): the closed forms above for
// neo-Hooke and linear, materials::evaluate for the others.
inline void fastPk2(const Hyperelastic& law, const Mat3& F, double J, Mat3& S, double& W) {
  if (law.kind == LawKind::NeoHookean) {
    neoHookeanPk2(law.C10, law.bulk, F, J, S, W);
  } else if (law.kind == LawKind::Linear) {
    stVenantKirchhoffPk2(lame(law.E, law.nu), F, S, W);
  } else {
    const Stress3 st = evaluate(law, F, false);
    S = st.S;
    W = st.energy;
  }
}

}  // namespace needlesim::materials
