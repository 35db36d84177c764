// realtime3d against realtime2d on a slab: a 3D block 1 mm thick with every node's z held is
// in plane strain, the model realtime2d solves with its 1 mm slab (seed 003 eqs 3.9-3.11).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "needlesim/engines/realtime2d/session.hpp"
#include "needlesim/engines/realtime3d/session.hpp"

namespace {
struct Outcome {
  double deflection = 0.0, force = 0.0, drag = 0.0;  // m, N, m (axial displacement of path node 3)
};

Outcome run2d(int nx, int ny) {
  auto c = needlesim::realtime2d::thesisGelatinConfig(nx, ny, needlesim::realtime2d::Backend::Direct);
  c.puncture_force = 0.0;
  needlesim::realtime2d::Session s(c);
  double d = -1e-3;
  while (d < 0.03) s.step(s.poseAtDepth(d += 3e-3 * c.dt), c.dt);
  return {s.last().tip_deflection, s.last().axial_force, s.tissue().nodeDisplacement(s.tissue().path()[3].node).x()};
}

Outcome run3d(int nx, int ny) {
  using namespace needlesim::realtime3d;
  auto c = gelatinBlockConfig(nx, ny, Backend::Direct);
  c.puncture_force = 0.0;
  c.tissue.block = {0.08, 0.12, 1e-3, nx, ny, 3, 0.0, 0.0, 1.0};
  c.tissue.hold_out_of_plane = true;
  // realtime2d couples at its grid's path nodes with no needle radius (thinner than the needle,
  // the slab could not hold its surface): points on the axis at the same spacing
  c.tissue.coupling_radius = 0.0;
  c.tissue.coupling_spacing = 0.08 / (nx - 1);
  Session s(c);
  double d = -1e-3;
  while (d < 0.03) s.step(s.poseAtDepth(d += 3e-3 * c.dt), c.dt);
  return {s.last().tip_deflection[0], s.last().axial_force, s.tissue().pathDisplacement(3).x()};
}
}  // namespace

// Same grid in the plane: bilinear quads (2D) against linear tetrahedra (3D, six per hexahedron).
// Constant-strain tets are stiffer than full-integration quads on one grid, so the two differ by a
// discretisation error of the order of the element size: the drag of a path node (the most local
// quantity) must come closer under refinement (4.4% -> 1.1% here); the tip deflection, set by the
// tissue's lateral stiffness along the whole shaft, within 5% (3-4% on both grids); the axial
// force, mostly the Karnopp friction law along the same contact length, within 1%.
TEST(Realtime3dSlab, PlaneStrainSlabConvergesToRealtime2d) {
  const Outcome a2 = run2d(11, 16), a3 = run3d(11, 16);
  const Outcome b2 = run2d(21, 31), b3 = run3d(21, 31);
  std::printf("coarse 2D %.4e %.4e %.4e 3D %.4e %.4e %.4e\nfine   2D %.4e %.4e %.4e 3D %.4e %.4e %.4e\n",
              a2.deflection, a2.force, a2.drag, a3.deflection, a3.force, a3.drag, b2.deflection, b2.force, b2.drag,
              b3.deflection, b3.force, b3.drag);
  auto rel = [](double x, double y) { return std::abs(x - y) / std::abs(y); };
  EXPECT_LT(rel(b3.deflection, b2.deflection), 0.05);
  EXPECT_LT(rel(b3.force, b2.force), 0.01);
  EXPECT_LT(rel(b3.drag, b2.drag), 0.5 * rel(a3.drag, a2.drag));
}
