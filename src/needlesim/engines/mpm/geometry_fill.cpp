// Imported geometry -> material points and held grid nodes (docs/models/mpm.md "Imported
// geometry"). Point in tetrahedron by barycentric coordinates; closest point on a triangle after
// Ericson, Real-Time Collision Detection (2005) section 5.1.5.
#include "needlesim/engines/mpm/geometry_fill.hpp"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>

#include "needlesim/mesh/boundary.hpp"
#include "needlesim/mesh/volume_mesh.hpp"

namespace needlesim::mpm {

namespace {

Vec3 nodeOf(const mesh::VolumeMesh& m, int n, const Vec3& shift) {
  const auto p = mesh::nodePoint(m, n);
  return Vec3(p[0], p[1], p[2]) + shift;
}

// Lattice index range [first, last] along d of the points within [a, b].
std::array<int, 2> latticeRange(const Lattice& L, int d, double a, double b) {
  const auto u = static_cast<std::size_t>(d);
  const int first = std::max(0, static_cast<int>(std::ceil((a - L.lo[d]) / L.sp[d] - 0.5)));
  const int last = std::min(L.n[u] - 1, static_cast<int>(std::floor((b - L.lo[d]) / L.sp[d] - 0.5)));
  return {first, last};
}


}  // namespace

std::vector<int> latticeRegions(const ImportedGeometry& g, const Lattice& L, const Vec3& shift) {
  const mesh::VolumeMesh& m = *g.mesh;
  std::vector<int> owner(L.size(), -1);
  const double tol = 1e-10;  // barycentric: a point on a shared face belongs to both
  for (int e = 0; e < m.elements(); ++e) {
    const int* c = &m.conn[static_cast<std::size_t>(4 * e)];
    const Vec3 x0 = nodeOf(m, c[0], shift);
    Eigen::Matrix3d T;
    for (int a = 1; a < 4; ++a) T.col(a - 1) = nodeOf(m, c[a], shift) - x0;
    const Eigen::Matrix3d Tinv = T.inverse();  // elements are non-degenerate (the reader checks)
    Vec3 lo = x0, hi = x0;
    for (int a = 1; a < 4; ++a) {
      lo = lo.cwiseMin(x0 + T.col(a - 1));
      hi = hi.cwiseMax(x0 + T.col(a - 1));
    }
    std::array<std::array<int, 2>, 3> r;
    for (int d = 0; d < 3; ++d) r[static_cast<std::size_t>(d)] = latticeRange(L, d, lo[d], hi[d]);
    for (int i = r[0][0]; i <= r[0][1]; ++i)
      for (int j = r[1][0]; j <= r[1][1]; ++j)
        for (int k = r[2][0]; k <= r[2][1]; ++k) {
          const std::size_t q = L.index(i, j, k);
          if (owner[q] >= 0) continue;
          const Vec3 b = Tinv * (L.point(i, j, k) - x0);
          if (b.minCoeff() >= -tol && b.sum() <= 1 + tol) owner[q] = g.region[static_cast<std::size_t>(e)];
        }
  }
  return owner;
}

std::vector<std::array<int, 3>> heldGridNodes(const ImportedGeometry& g, const MpmConfig& cfg, const Vec3& shift) {
  const mesh::VolumeMesh& m = *g.mesh;
  const double h = cfg.h, reach = 2.0 * h, tol = 1e-6 * h;
  std::vector<char> held(static_cast<std::size_t>(cfg.cells[0] + 1) * (cfg.cells[1] + 1) * (cfg.cells[2] + 1), 0);
  std::vector<std::array<int, 3>> out;
  for (const mesh::Facet& f : mesh::boundaryFacets(m)) {
    if (f.nodes.size() != 3) continue;  // tetrahedra only (the engine refuses other elements)
    if (!std::all_of(f.nodes.begin(), f.nodes.end(), [&](int n) { return g.supported[static_cast<std::size_t>(n)]; }))
      continue;
    const Vec3 a = nodeOf(m, f.nodes[0], shift), b = nodeOf(m, f.nodes[1], shift), c = nodeOf(m, f.nodes[2], shift);
    const Vec3 normal(f.normal[0], f.normal[1], f.normal[2]);
    const Vec3 lo = a.cwiseMin(b).cwiseMin(c).array() - reach, hi = a.cwiseMax(b).cwiseMax(c).array() + reach;
    std::array<int, 3> first{}, last{};
    for (int d = 0; d < 3; ++d) {
      const auto u = static_cast<std::size_t>(d);
      first[u] = std::max(0, static_cast<int>(std::ceil((lo[d] - cfg.origin[d]) / h)));
      last[u] = std::min(cfg.cells[u], static_cast<int>(std::floor((hi[d] - cfg.origin[d]) / h)));
    }
    for (int i = first[0]; i <= last[0]; ++i)
      for (int j = first[1]; j <= last[1]; ++j)
        for (int k = first[2]; k <= last[2]; ++k) {
          const std::size_t I = (static_cast<std::size_t>(i) * (cfg.cells[1] + 1) + j) * (cfg.cells[2] + 1) + k;
          if (held[I]) continue;
          const Vec3 x = cfg.origin + h * Vec3(i, j, k);
          const Vec3 p = closestOnTriangle(x, a, b, c);
          if ((x - p).norm() > reach || (x - p).dot(normal) < -tol) continue;
          held[I] = 1;
          out.push_back({i, j, k});
        }
  }
  return out;
}

}  // namespace needlesim::mpm
