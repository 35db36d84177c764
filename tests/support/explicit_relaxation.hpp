#pragma once
// The explicit solver (engines/explicit/solver.hpp) on a realtime3d block's tets, held as realtime3d holds the
// block (four sides and the far face), with mass-proportional damping of 300/s, about twice the block's lowest
// frequency: near-critical dynamic relaxation to the static solution the real-time engine is compared with.
#include <memory>

#include "needlesim/engines/explicit/solver.hpp"
#include "needlesim/materials/material_spec.hpp"

namespace needlesim::testing {

template <class Mesh, class Block>
std::unique_ptr<explicit_fe::ExplicitSolver> relaxingExplicitBlock(const Mesh& mesh, const Block& b,
                                                                   const materials::MaterialSpec& ms) {
  explicit_fe::SolverOptions o;
  o.damping = 300.0;
  o.nodalPressure = false;  // plain constant-strain tets, as realtime3d (its anti-locking pressure is a different element)
  auto ex = std::make_unique<explicit_fe::ExplicitSolver>(mesh, std::vector{explicit_fe::Material::fromSpec(ms)}, o);
  const int held = ex->addGroup();
  for (int n = 0; n < mesh.nodes(); ++n) {
    const double x = mesh.coord(n, 0), y = mesh.coord(n, 1), z = mesh.coord(n, 2);
    if (x > b.length - 1e-12 || y < 1e-12 || y > b.width - 1e-12 || z < 1e-12 || z > b.height - 1e-12)
      for (int i = 0; i < 3; ++i) ex->addDof(held, n, i);
  }
  return ex;
}

}  // namespace needlesim::testing
