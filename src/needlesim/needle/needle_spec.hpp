#pragma once
// The needle as a scenario gives it (needle section): dimensions, tip and material.

namespace needlesim {

enum class TipType { Bevel, Conical, Blunt };

struct NeedleSpec {
  double outer_diameter = 0.0;  // m
  double inner_diameter = 0.0;  // m (0 = solid)
  double length = 0.0;          // m
  double bevel_angle = 20.0 * (3.14159265358979323846 / 180.0);  // rad (tip angle alpha), 20 deg
  TipType tip = TipType::Bevel;
  double youngs_modulus = 200e9;  // Pa (steel)
  double poisson = 0.3;
  double density = 7850.0;  // kg/m^3 (steel)
};

}  // namespace needlesim
