#pragma once
// A tissue law as an engine uses it: a hyperelastic law wrapped by its Prony
// series (QLV, viscoelastic.hpp) applied to the second Piola-Kirchhoff stress.
// Value semantics: evaluating a trial deformation never changes the committed
// state; an engine keeps the returned state when its step is accepted (so
// Newton iterations may evaluate as often as they like).
#include <Eigen/Core>

#include "needlesim/materials/hyperelastic.hpp"
#include "needlesim/materials/material_spec.hpp"
#include "needlesim/materials/viscoelastic.hpp"

namespace needlesim::materials {

struct TissueLaw {
  Hyperelastic elastic;
  Prony prony;  // empty: purely hyperelastic
  static TissueLaw fromSpec(const MaterialSpec& spec);  // validates both parts
  bool viscous() const { return !prony.terms.empty(); }
};

using Voigt4 = Eigen::Vector4d;                // plane strain S: 11, 22, 12, 33
using Voigt6 = Eigen::Matrix<double, 6, 1>;    // 3D S: 11, 22, 33, 12, 23, 13

struct PointState2 {
  PronyState<Voigt4> prony;
};
struct PointState3 {
  PronyState<Voigt6> prony;
};

// Stress at F after a step dt from the committed state `state`; the state for
// commit is written to `next`. The tangent is the algorithmic one,
// stepFactor(dt) times the elastic tangent (exact for QLV). sigma is
// J^-1 F S F^T of the viscoelastic S; the energy is the elastic one.
Stress2 evaluatePlaneStrain(const TissueLaw& law, const PointState2& state, const Mat2& F, double dt,
                            PointState2& next, bool withTangent = true);
Stress3 evaluate(const TissueLaw& law, const PointState3& state, const Mat3& F, double dt, PointState3& next,
                 bool withTangent = true);

}  // namespace needlesim::materials
