#pragma once
// Velocity conditions on the MPM background grid: per node the fixed
// velocity components (fixed and roller faces, held nodes of an imported
// geometry's supported side) and the Lysmer-Kuhlemeyer dashpots of the
// non-reflecting faces (tributary area h^2). The grid update applies them.
#include <cstdint>
#include <vector>

#include "needlesim/engines/mpm/mpm_config.hpp"
#include "needlesim/engines/mpm/mpm_material.hpp"

namespace needlesim::mpm {

struct GridBoundaries {
  std::vector<std::uint8_t> fixMask;  // per node: bits 0-2 fixed velocity components
  std::vector<double> dashpot;        // per node: 3 viscous coefficients (non-reflecting), kg/s
  // For the grid of nn[3] nodes of cfg; m0: the material of the dashpots (none: no dashpots).
  void build(const MpmConfig& cfg, const int* nn, const MpmMaterial* m0);
};

}  // namespace needlesim::mpm
