#pragma once
// Hyperelastic tissue laws: strain energy, second Piola-Kirchhoff and Cauchy
// stress and the consistent material tangent, in 3D and 2D plane strain.
// Conventions (docs/models/materials.md):
//   W(C) = W_iso(I1bar, I2bar, lambda_bar) + U(J),  U(J) = K/2 (J - 1)^2  (ABAQUS, D1 = 2/K)
//   S = 2 dW/dC,  sigma = J^-1 F S F^T,  CC = 4 d2W/dCdC  (dS = CC : dE, E = (C - I)/2)
// Tangents are 6x6 (3D) or 3x3 (2D) matrices of tensor components in Voigt
// order 11, 22, 33, 12, 23, 13 (2D: 11, 22, 12): dS_I = sum_J CC_IJ gamma_J,
// gamma the engineering strain increment (gamma_12 = 2 dE_12).
#include <Eigen/Core>
#include <array>
#include <string>
#include <vector>

#include "needlesim/materials/elastic_moduli.hpp"
#include "needlesim/materials/laws/law_list.hpp"
#include "needlesim/materials/material_spec.hpp"

namespace needlesim::materials {

// One enumerator per law of the registry (laws/law_list.hpp), in its order.
#define NEEDLESIM_LAW_KIND(kind, fn) kind,
enum class LawKind { NEEDLESIM_LAWS(NEEDLESIM_LAW_KIND) };
#undef NEEDLESIM_LAW_KIND

LawKind lawKind(const std::string& name);  // throws Error for an unknown name
std::string lawName(LawKind kind);

// One law with its parameters in SI. Build with fromSpec (validated) or fill directly.
// What each law is (parameters, energy, moduli) is its unit in laws/.
struct Hyperelastic {
  LawKind kind = LawKind::NeoHookean;
  // linear (St Venant-Kirchhoff at finite strain): E, nu
  double E = 0.0, nu = 0.0;
  // invariant laws
  double C10 = 0.0, C01 = 0.0, C20 = 0.0, C30 = 0.0;
  // Ogden: W = sum_p mu_p / alpha_p (l1^a + l2^a + l3^a - 3), up to 3 terms (isochoric stretches)
  std::vector<double> ogdenMu, ogdenAlpha;
  // Fung-Demiray (seed 000 eq 8): W = mu / (2 gamma) [exp(gamma (I1bar - 3)) - 1]
  double mu = 0.0, gamma = 0.0;
  // Volumetric part (not used by linear): bulk modulus K, Pa
  double bulk = 0.0;
  // Parameters of a law that no field above holds, in the order its unit (laws/) reads them.
  std::array<double, 4> own{};

  static Hyperelastic fromSpec(const MaterialSpec& spec);  // validates; throws Error
  double initialShear() const;                             // mu0, Pa
  double initialBulk() const;                              // K0, Pa: E / (3 (1 - 2 nu)) for linear, else bulk
  // Small-strain Lame constants: lame(E, nu) for linear, else (K - 2/3 mu0, mu0).
  Lame initialLame() const;
  // Checks that parameters are finite and stable; throws Error naming the parameter.
  void validate() const;
};

using Mat3 = Eigen::Matrix3d;
using Mat2 = Eigen::Matrix2d;
using Tangent3 = Eigen::Matrix<double, 6, 6>;
using Tangent2 = Eigen::Matrix3d;

struct Stress3 {
  double energy = 0.0;  // J/m^3 (reference volume)
  Mat3 S = Mat3::Zero();
  Mat3 sigma = Mat3::Zero();
  Tangent3 tangent = Tangent3::Zero();  // filled when asked for
};

struct Stress2 {
  double energy = 0.0;
  Mat2 S = Mat2::Zero();
  Mat2 sigma = Mat2::Zero();
  double sigma33 = 0.0;  // out-of-plane Cauchy stress of the plane-strain state
  Tangent2 tangent = Tangent2::Zero();
};

// Throws SolverError when det F <= 0 (an inverted element).
Stress3 evaluate(const Hyperelastic& law, const Mat3& F, bool withTangent = true);
Stress2 evaluatePlaneStrain(const Hyperelastic& law, const Mat2& F, bool withTangent = true);

double strainEnergy(const Hyperelastic& law, const Mat3& F);
Mat3 secondPiolaKirchhoff(const Hyperelastic& law, const Mat3& F);
Mat3 cauchyStress(const Hyperelastic& law, const Mat3& F);

// Voigt helpers (order 11, 22, 33, 12, 23, 13).
inline constexpr int kVoigt3[6][2] = {{0, 0}, {1, 1}, {2, 2}, {0, 1}, {1, 2}, {0, 2}};
inline constexpr int kVoigt2[3][2] = {{0, 0}, {1, 1}, {0, 1}};

}  // namespace needlesim::materials
