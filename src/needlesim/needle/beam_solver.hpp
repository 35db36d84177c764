#pragma once
// Linear static Euler-Bernoulli beam, straight, uniform elements, on an optional
// Winkler foundation (stiffness per unit length per element). Small, general
// solver used by tests (cantilever, Hetenyi) and by any engine needing a
// quick shaft solution. Dofs per node: (w, theta).
#include <vector>

#include "needlesim/needle/banded.hpp"

namespace needlesim::needle {

struct StraightBeam {
  double EI = 0.0;                 // N m^2
  double length = 0.0;             // m
  int elements = 10;
  std::vector<double> foundation;  // N/m^2 per element (empty = none)
  double axial_force = 0.0;        // N, tension positive (geometric stiffness)
  bool clamp_left = true;          // w = theta = 0 at x = 0
  bool pin_left = false;           // w = 0 at x = 0 (ignored when clamped)
};

struct NodalLoad {
  int node = 0;
  double force = 0.0;   // N, along +w
  double moment = 0.0;  // N m, counter-clockwise
};

struct BeamSolution {
  std::vector<double> x, w, theta;  // per node
};

BeamSolution solveStraightBeam(const StraightBeam& beam, const std::vector<NodalLoad>& loads);

}  // namespace needlesim::needle
