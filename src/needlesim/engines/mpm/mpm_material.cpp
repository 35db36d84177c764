// The MPM tissue material and its stress (mpm_material.hpp): the closed forms
// of materials/stress_lanes.hpp for Fung-Demiray and neo-Hookean (seed 000 eqs
// 8-13), St Venant-Kirchhoff, the materials library otherwise; the wave speed
// of eq 27.
#include "needlesim/engines/mpm/mpm_material.hpp"

#include <Eigen/LU>
#include <cmath>

#include "needlesim/engines/mpm/pass_support.hpp"
#include "needlesim/materials/fast_stress.hpp"

namespace needlesim::mpm {

using pass::A4;

MpmMaterial MpmMaterial::fromSpec(const materials::MaterialSpec& spec) {
  MpmMaterial m;
  m.law = materials::Hyperelastic::fromSpec(spec);
  m.density = spec.density;
  return m;
}

// Stress update (Cauchy, stored on the particle), energy density per reference
// volume and the current dilatational wave speed (eq 27 with the current
// tangent shear modulus of the law).
MPM_CLONES Mat3 evaluateStress(const MpmMaterial& m, const Mat3& F, double massScaling, double& W, double& wave) {
  const auto& L = m.law;
  if (materials::lanes::hasLanes(L)) {
    // Fung-Demiray and neo-Hookean: the closed form of materials/stress_lanes.hpp
    // (seed 000 eqs 8-13), one point in all four lanes.
    A4 Fl[9], sl[6], W4, wave4;
    for (int c = 0; c < 9; ++c) Fl[c] = A4{} + F(c / 3, c % 3);
    materials::lanes::hyperelasticStress4(L, m.density * massScaling, Fl, sl, W4, wave4);
    W = W4[0];
    wave = wave4[0];
    Mat3 sigma;
    sigma << sl[0][0], sl[3][0], sl[5][0], sl[3][0], sl[1][0], sl[4][0], sl[5][0], sl[4][0], sl[2][0];
    return sigma;
  }
  const double J = F.determinant();
  Mat3 sigma;
  double muc = 0.0, K = 0.0;
  using materials::LawKind;
  if (L.kind == LawKind::Linear) {
    // St Venant-Kirchhoff, the library's "linear" law (materials/fast_stress.hpp).
    const materials::Lame l = materials::lame(L.E, L.nu);
    Mat3 S;
    materials::stVenantKirchhoffPk2(l, F, S, W);
    sigma = F * S * F.transpose() / J;
    muc = l.mu;
    K = l.lambda + 2.0 / 3.0 * l.mu;
  } else {
    materials::Stress3 s = materials::evaluate(L, F, false);
    sigma = s.sigma;
    W = s.energy;
    muc = L.initialShear();
    K = L.bulk;
  }
  const double rho = m.density * massScaling / J;
  wave = std::sqrt((K + 4.0 / 3.0 * muc) / rho);
  return sigma;
}

}  // namespace needlesim::mpm
