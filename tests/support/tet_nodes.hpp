// The realtime3d mesh node nearest to a point, for tests that read a node where the engine reads
// a marker or the explicit engine a displacement.
#pragma once

#include <Eigen/Core>

#include "needlesim/engines/realtime3d/fe.hpp"

namespace needlesim::testing {

inline int nearestNode(const realtime3d::TetMesh& m, const Eigen::Vector3d& p) {
  const auto at = [&](int n) { return Eigen::Vector3d(m.coord(n, 0), m.coord(n, 1), m.coord(n, 2)); };
  int best = 0;
  for (int n = 1; n < m.nodes(); ++n)
    if ((at(n) - p).norm() < (at(best) - p).norm()) best = n;
  return best;
}

}  // namespace needlesim::testing
