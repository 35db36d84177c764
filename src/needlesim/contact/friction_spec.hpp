#pragma once
// The friction of a tissue layer along the shaft (tissue.layers[].friction), as the
// contact laws (contact/karnopp.hpp, contact/coulomb.hpp) take it.

namespace needlesim {

// Modified Karnopp friction along the shaft, per unit length in contact
// (seed 003 eq 3.23 with the per-length coefficients of eq 5.1).
struct FrictionSpec {
  double C_p = 0.0;          // N/m, dynamic friction, insertion
  double b_p = 0.0;          // N s/m^2, damping, insertion
  double C_n = 0.0;          // N/m, dynamic friction, retraction (magnitude)
  double b_n = 0.0;          // N s/m^2, damping, retraction
  double D_p = 0.0;          // N/m, static friction limit, positive direction
  double D_n = 0.0;          // N/m, static friction limit, negative direction (magnitude)
  double static_band = 0.0;  // m/s, Delta v: |v| < Delta v/2 counts as sticking
  double coefficient = 0.0;  // Coulomb coefficient for contact engines (seed 001: 0.3)
};

}  // namespace needlesim
