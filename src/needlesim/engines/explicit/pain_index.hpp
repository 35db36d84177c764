#pragma once
// Pain index PDI of seed 001 section 4.4 (eqs 7-8), computed from a needle
// force record: sigma = F / (pi (R^2 - r^2)) (eq 7, R and r read as the outer and
// inner RADII: the needle's annular cross-section) and PDI = sigma / sigma*
// (eq 8), sigma* the tissue's stress at 0.3 strain ("basic stress": nominal
// stress in uniaxial compression to stretch 0.7, incompressible response of the
// layer's law). Interpretation choices: docs/validation/cohesive.md "Seed 001 studies".
#include <vector>

#include "needlesim/materials/material_spec.hpp"

namespace needlesim::explicit_fe {

// pi (R^2 - r^2) from the outer and inner diameters (inner 0: solid needle), m^2.
double needleAnnulusArea(double outerDiameter, double innerDiameter);

// |nominal stress| of the law in uniaxial compression at engineering strain `strain`, Pa.
double painBasicStress(const materials::MaterialSpec& spec, double strain = 0.3);

struct PainIndex {
  double area = 0.0;         // m^2, eq 7 denominator
  double basicStress = 0.0;  // Pa, sigma*
  double peakStress = 0.0;   // Pa, largest F / area
  double peak = 0.0;         // largest PDI (eq 8)
  double mean = 0.0;         // time-average of PDI over the record (trapezoidal in time)
};

// PDI of a force record F(t) (N; negative forces count as 0: the needle pulls, nothing presses).
PainIndex painIndex(const std::vector<double>& time, const std::vector<double>& force, double area,
                    double basicStress);

}  // namespace needlesim::explicit_fe
