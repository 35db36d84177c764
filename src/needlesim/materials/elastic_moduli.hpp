#pragma once
// Isotropic small-strain moduli: the one conversion from Young's modulus E
// and Poisson's ratio nu to the Lame constants lambda, mu (seed 003 eqs
// 3.10-3.11) and the bulk modulus K, and back. Every engine and the laws take
// their moduli from here (docs/models/materials.md "Small-strain moduli").
namespace needlesim::materials {

struct Lame {
  double lambda = 0.0;  // Pa, first Lame constant
  double mu = 0.0;      // Pa, shear modulus
};

// lambda = E nu / ((1 + nu)(1 - 2 nu)), mu = E / (2 (1 + nu)); -1 < nu < 1/2.
constexpr Lame lame(double E, double nu) noexcept {
  return {E * nu / ((1.0 + nu) * (1.0 - 2.0 * nu)), E / (2.0 * (1.0 + nu))};
}

// K = E / (3 (1 - 2 nu)) (= lambda + 2/3 mu up to rounding).
constexpr double bulkModulus(double E, double nu) noexcept { return E / (3.0 * (1.0 - 2.0 * nu)); }

// K of a material given by its shear modulus mu and nu: E = 2 mu (1 + nu).
constexpr double bulkFromShear(double mu, double nu) noexcept { return bulkModulus(2.0 * mu * (1.0 + nu), nu); }

// The inverse, from the bulk and shear moduli: E = 9 K mu / (3 K + mu),
// nu = (3 K - 2 mu) / (2 (3 K + mu)).
struct YoungPoisson {
  double E = 0.0, nu = 0.0;
};
constexpr YoungPoisson youngPoisson(double bulk, double shear) noexcept {
  return {9.0 * bulk * shear / (3.0 * bulk + shear), (3.0 * bulk - 2.0 * shear) / (2.0 * (3.0 * bulk + shear))};
}

}  // namespace needlesim::materials
