#pragma once
// A tissue material of the MPM solver (the hyperelastic law and its density)
// and its Cauchy stress at a deformation gradient (seed 000 eqs 8-13, 27).
#include <Eigen/Core>

#include "needlesim/materials/hyperelastic.hpp"

namespace needlesim::mpm {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;

// A tissue material as the solver uses it: the law plus the data of a fast path.
struct MpmMaterial {
  materials::Hyperelastic law;
  double density = 1000.0;  // kg/m^3, before mass scaling
  // Coulomb coefficient of the grid contact with a rigid body where this
  // material's point is nearest to it (eq 20); < 0: the rigid body's own.
  double rigidFriction = -1.0;
  static MpmMaterial fromSpec(const materials::MaterialSpec& spec);
};

// Cauchy stress of a material at F (fast closed forms for Fung-Demiray,
// neo-Hookean and St Venant-Kirchhoff; the materials library otherwise), the
// energy per reference volume W and the current dilatational wave speed (eq 27).
Mat3 evaluateStress(const MpmMaterial& m, const Mat3& F, double massScaling, double& W, double& wave);

}  // namespace needlesim::mpm
