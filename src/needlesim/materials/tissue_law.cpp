#include "needlesim/materials/tissue_law.hpp"

#include <Eigen/LU>

namespace needlesim::materials {

TissueLaw TissueLaw::fromSpec(const MaterialSpec& spec) {
  TissueLaw t;
  t.elastic = Hyperelastic::fromSpec(spec);
  t.prony.terms = spec.prony;
  t.prony.validate();
  return t;
}

Stress2 evaluatePlaneStrain(const TissueLaw& law, const PointState2& state, const Mat2& F, double dt,
                            PointState2& next, bool withTangent) {
  Stress2 s = evaluatePlaneStrain(law.elastic, F, withTangent);
  next = state;
  if (!law.viscous()) return s;
  const double J = F.determinant();
  // S33 = J sigma33 (F33 = 1) relaxes with the in-plane components
  Voigt4 Se(s.S(0, 0), s.S(1, 1), s.S(0, 1), J * s.sigma33);
  Voigt4 S = pronyUpdate(law.prony, next.prony, Se, dt);
  s.S << S[0], S[2], S[2], S[1];
  s.sigma = F * s.S * F.transpose() / J;
  s.sigma33 = S[3] / J;
  if (withTangent) s.tangent *= law.prony.stepFactor(dt);
  return s;
}

Stress3 evaluate(const TissueLaw& law, const PointState3& state, const Mat3& F, double dt, PointState3& next,
                 bool withTangent) {
  Stress3 s = evaluate(law.elastic, F, withTangent);
  next = state;
  if (!law.viscous()) return s;
  Voigt6 Se;
  for (int I = 0; I < 6; ++I) Se[I] = s.S(kVoigt3[I][0], kVoigt3[I][1]);
  Voigt6 S = pronyUpdate(law.prony, next.prony, Se, dt);
  for (int I = 0; I < 6; ++I) {
    s.S(kVoigt3[I][0], kVoigt3[I][1]) = S[I];
    s.S(kVoigt3[I][1], kVoigt3[I][0]) = S[I];
  }
  s.sigma = F * s.S * F.transpose() / F.determinant();
  if (withTangent) s.tangent *= law.prony.stepFactor(dt);
  return s;
}

}  // namespace needlesim::materials
