#pragma once
// Bevel-tip loads, seed 002 eqs 20-26 (Misra et al. 2010, section 3.1).
// Frame of seed 002 Fig 13: x along the needle axis towards the tissue, y
// transverse, the bevel face on the +y side; M is positive counter-clockwise.
// A negative Q pushes the tip towards -y, the side of the sharp point.

namespace needlesim::needle {

struct TipLoadInput {
  double K_T = 0.0;      // N/m^2, needle-tissue interaction stiffness per unit length (eq 13)
  double diameter = 0.0; // m, d
  double alpha = 0.0;    // rad, bevel angle
  double beta = 0.0;     // rad, cut angle, 0 <= beta <= alpha
  double P_input = 0.0;  // N, insertion force
};

struct TipLoads {
  double P = 0.0;  // N, axial resultant (eq 24)
  double Q = 0.0;  // N, transverse resultant (eq 25)
  double M = 0.0;  // N m, moment about the tip (eq 26)
  // geometry of Fig 13
  double a = 0.0, b = 0.0, e = 0.0, gamma = 0.0;
  double F1 = 0.0;  // N, bottom-edge resultant (eq 22)
  double F2 = 0.0;  // N, bevel-edge resultant (eq 23)
};

// Throws std::invalid_argument outside 0 < alpha < pi/2, 0 <= beta <= alpha, d > 0, K_T >= 0.
TipLoads bevelTipLoads(const TipLoadInput& in);

}  // namespace needlesim::needle
