// Seed 003's lumped force model (thesis eqs 3.23-3.24 with the section 5.1 constants) against the
// engines' forces table, for the thesis-experiment tests of realtime2d and realtime3d.
#pragma once

#include <stdexcept>

#include "needlesim/io/table.hpp"

namespace needlesim::thesis {

// The closed form while the needle slides at speed v with its tip at depth d: every path node
// slips at v, so the shaft friction is (C_p + b_p v) d, plus the constant cutting force F_c.
inline double axialForce(double v, double d, double cutting) { return (3.791 + 285.053 * v) * d + cutting; }

struct ForceSample {
  double depth = 0.0, velocity = 0.0, force = 0.0;
};

// The last row of the forces table in which the needle still moves: the closed form's condition
// (once it stops, the b_p v part relaxes with the tissue).
inline ForceSample lastMovingForce(const io::Table& forces) {
  const auto depth = forces.column("depth"), v = forces.column("velocity"), F = forces.column("force_total");
  for (std::size_t i = depth.size(); i-- > 0;)
    if (v[i] > 0.0) return {depth[i], v[i], F[i]};
  throw std::runtime_error("the forces table has no row with the needle moving");
}

}  // namespace needlesim::thesis
