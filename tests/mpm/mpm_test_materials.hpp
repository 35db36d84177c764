#pragma once
// Materials shared by the MPM solver tests.
#include "needlesim/engines/mpm/mpm_solver.hpp"

namespace needlesim::mpm::test {

// St Venant-Kirchhoff ("linear" law of the materials library).
inline MpmMaterial linearMaterial(double E, double nu, double rho) {
  MpmMaterial m;
  m.law.kind = materials::LawKind::Linear;
  m.law.E = E;
  m.law.nu = nu;
  m.density = rho;
  return m;
}

// Name of a shape function for the tests' printed lines.
inline const char* shapeName(Shape s) { return s == Shape::Linear ? "linear" : "B-spline"; }

}  // namespace needlesim::mpm::test
