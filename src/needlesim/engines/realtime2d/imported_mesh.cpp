#include "needlesim/engines/realtime2d/imported_mesh.hpp"

#include <algorithm>
#include <cmath>

#include "needlesim/core/error.hpp"
#include "needlesim/mesh/boundary.hpp"
#include "needlesim/needle/insertion_frame.hpp"

namespace needlesim::realtime2d {

namespace {
double signedArea(const Eigen::Matrix2Xd& x, const Eigen::Vector4i& q) {
  double a = 0.0;
  for (int k = 0; k < 4; ++k) {
    const Eigen::Vector2d p = x.col(q[k]), r = x.col(q[(k + 1) % 4]);
    a += 0.5 * (p.x() * r.y() - r.x() * p.y());
  }
  return a;
}

// Local element size at each node: the largest sqrt(area) of the elements around it.
std::vector<double> nodeSizes(const Mesh& mesh) {
  std::vector<double> h(static_cast<std::size_t>(mesh.nodeCount()), 0.0);
  for (int e = 0; e < mesh.elementCount(); ++e) {
    const double size = std::sqrt(std::abs(signedArea(mesh.nodes, mesh.quads.col(e))));
    for (int a = 0; a < 4; ++a) {
      auto& v = h[static_cast<std::size_t>(mesh.quads(a, e))];
      v = std::max(v, size);
    }
  }
  return h;
}
}  // namespace

Mesh importedMesh(const ImportedGeometry& g, const Eigen::Vector2d& shift) {
  const auto& vm = *g.mesh;
  if (vm.dim != 2 || (vm.element != "tri3" && vm.element != "quad4"))
    throw SolverError("realtime2d: an imported mesh must be 2D of tri3 or quad4 elements, not " + vm.element);
  Mesh m;
  m.triangles = vm.element == "tri3";
  m.nodes.resize(2, vm.nodes());
  for (int n = 0; n < vm.nodes(); ++n)
    m.nodes.col(n) = Eigen::Vector2d(vm.X[static_cast<std::size_t>(2 * n)], vm.X[static_cast<std::size_t>(2 * n + 1)]) + shift;
  const int npe = vm.nodesPerElement();
  m.quads.resize(4, vm.elements());
  for (int e = 0; e < vm.elements(); ++e) {
    Eigen::Vector4i q;
    for (int a = 0; a < 4; ++a) q[a] = vm.conn[static_cast<std::size_t>(e * npe + std::min(a, npe - 1))];
    if (signedArea(m.nodes, q) < 0.0) std::swap(q[1], q[npe - 1]);  // clockwise in the file: turn it
    if (npe == 3) q[3] = q[2];
    m.quads.col(e) = q;
  }
  m.extent_x = m.nodes.row(0).maxCoeff();
  m.extent_y = m.nodes.row(1).maxCoeff();
  return m;
}

std::vector<bool> importedHeld(const ImportedGeometry& g) {
  std::vector<bool> held(g.supported.size(), false);
  for (std::size_t n = 0; n < held.size(); ++n) held[n] = g.supported[n] != 0;
  for (const auto& f : mesh::boundaryFacets(*g.mesh))
    if (std::abs(f.normal[1]) > std::abs(f.normal[0]))
      for (int n : f.nodes) held[static_cast<std::size_t>(n)] = true;
  return held;
}

std::vector<PathNode> pathNearAxis(const Mesh& mesh, const std::vector<bool>& held, const Eigen::Vector2d& entry,
                                   const Eigen::Vector2d& t) {
  const Eigen::Vector2d nrm(-t.y(), t.x());
  const auto h = nodeSizes(mesh);
  std::vector<PathNode> near;
  for (int n = 0; n < mesh.nodeCount(); ++n) {
    const Eigen::Vector2d d = mesh.nodes.col(n) - entry;
    const PathNode p{n, d.dot(t), d.dot(nrm)};
    if (!held[static_cast<std::size_t>(n)] && p.s >= -1e-12 && std::abs(p.offset) <= 0.5 * h[static_cast<std::size_t>(n)])
      near.push_back(p);
  }
  std::sort(near.begin(), near.end(), [](const PathNode& a, const PathNode& b) { return a.s < b.s; });
  std::vector<PathNode> path;
  for (const auto& p : near) {
    if (path.empty()) { path.push_back(p); continue; }
    PathNode& last = path.back();
    const double gap = 0.3 * std::max(h[static_cast<std::size_t>(p.node)], h[static_cast<std::size_t>(last.node)]);
    if (p.s - last.s >= gap) path.push_back(p);
    else if (std::abs(p.offset) < std::abs(last.offset)) last = p;
  }
  return path;
}

std::vector<PathNode> importedPath(const ImportedGeometry& g, double width, const Eigen::Vector2d& entry,
                                   const Eigen::Vector2d& axis) {
  TissueSpec block;
  block.width = width;
  const Eigen::Vector2d shift = needle::cornerShift(block).head<2>();
  return pathNearAxis(importedMesh(g, shift), importedHeld(g), entry + shift, axis.normalized());
}

double exitAlongAxis(const ImportedGeometry& g, const Eigen::Vector2d& entry, const Eigen::Vector2d& axis) {
  // From beyond the geometry back along the axis: the first crossing is the last exit.
  const double diag = std::hypot(g.hi[0] - g.lo[0], g.hi[1] - g.lo[1]);
  const double far = std::abs(entry.x() - g.lo[0]) + std::abs(entry.y()) + std::abs(g.lo[1]) + std::abs(g.hi[1]) +
                     std::abs(g.hi[0]) + 2.0 * diag;
  const Eigen::Vector2d from = entry + far * axis;
  const auto back = mesh::firstCrossing(*g.mesh, mesh::boundaryFacets(*g.mesh), {from.x(), from.y(), 0.0},
                                        {-axis.x(), -axis.y(), 0.0});
  if (!back) throw SolverError("realtime2d: the needle axis does not cross the imported mesh");
  return far - *back;
}

}  // namespace needlesim::realtime2d
