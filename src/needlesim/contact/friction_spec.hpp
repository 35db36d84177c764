#pragma once
// The friction along the shaft as two named laws, each with its own coefficients:
// Karnopp (contact/karnopp.hpp) and Coulomb (contact/coulomb.hpp). A layer's friction
// (tissue.layers[].friction) holds the coefficients of both; each engine applies one law
// (EngineInfo::friction, engines/registry.cpp) and reads only that law's coefficients.

namespace needlesim {

// Modified Karnopp friction along the shaft, per unit length in contact
// (seed 003 eq 3.23 with the per-length coefficients of eq 5.1).
struct KarnoppFriction {
  double C_p = 0.0;          // N/m, dynamic friction, insertion
  double b_p = 0.0;          // N s/m^2, damping, insertion
  double C_n = 0.0;          // N/m, dynamic friction, retraction (magnitude)
  double b_n = 0.0;          // N s/m^2, damping, retraction
  double D_p = 0.0;          // N/m, static friction limit, positive direction
  double D_n = 0.0;          // N/m, static friction limit, negative direction (magnitude)
  double static_band = 0.0;  // m/s, Delta v: |v| < Delta v/2 counts as sticking
};

// Coulomb friction of the contact engines: tangential force at most mu times the normal force
// (seed 001: mu 0.3 on the needle wall; seed 000 eqs 19-21).
struct CoulombFriction {
  double coefficient = 0.0;  // mu
};

// The law an engine applies along the shaft (None: it models no shaft friction).
enum class FrictionLaw { None, Karnopp, Coulomb };

// A layer's friction: the coefficients of both laws, as the scenario's friction section gives them.
struct FrictionSpec : KarnoppFriction, CoulombFriction {};

}  // namespace needlesim
