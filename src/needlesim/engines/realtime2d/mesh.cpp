#include "needlesim/engines/realtime2d/mesh.hpp"

#include <cmath>
#include <string>

#include "needlesim/core/error.hpp"

namespace needlesim::realtime2d {

namespace {
// m intervals over distance D, first (finest) spacing next to the path, each
// interval r times the previous, last/first = grading.
std::vector<double> gradedSide(double D, int m, double grading) {
  std::vector<double> h(static_cast<std::size_t>(m));
  if (m == 1 || std::abs(grading - 1.0) < 1e-12) {
    for (auto& v : h) v = D / m;
    return h;
  }
  const double r = std::pow(grading, 1.0 / (m - 1));
  const double h0 = D * (r - 1.0) / (std::pow(r, m) - 1.0);
  double hk = h0;
  for (auto& v : h) { v = hk; hk *= r; }
  return h;
}
}  // namespace

std::vector<double> gradedCoordinates(double width, double path_y, int nodes, double grading) {
  if (!(width > 0.0) || nodes < 3 || !(grading >= 1.0))
    throw SolverError("realtime2d mesh: need width > 0, at least 3 lateral nodes and grading >= 1");
  if (!(path_y > 0.0 && path_y < width))
    throw SolverError("realtime2d mesh: the needle path (y = " + std::to_string(path_y) +
                      " m) must lie strictly inside the width 0.." + std::to_string(width) + " m");
  const int intervals = nodes - 1;
  // Split intervals between the two sides in proportion to their widths (at least 1 each).
  int below = static_cast<int>(std::lround(intervals * path_y / width));
  below = std::max(1, std::min(intervals - 1, below));
  const int above = intervals - below;
  std::vector<double> y(static_cast<std::size_t>(nodes));
  const auto hb = gradedSide(path_y, below, grading);
  const auto ha = gradedSide(width - path_y, above, grading);
  y[static_cast<std::size_t>(below)] = path_y;
  for (int k = 0; k < below; ++k)
    y[static_cast<std::size_t>(below - 1 - k)] = y[static_cast<std::size_t>(below - k)] - hb[static_cast<std::size_t>(k)];
  for (int k = 0; k < above; ++k)
    y[static_cast<std::size_t>(below + 1 + k)] = y[static_cast<std::size_t>(below + k)] + ha[static_cast<std::size_t>(k)];
  y.front() = 0.0;
  y.back() = width;
  return y;
}

Mesh generateMesh(const MeshSpec& s) {
  if (!(s.length > 0.0) || s.nodes_depth < 2)
    throw SolverError("realtime2d mesh: need length > 0 and at least 2 nodes along the depth");
  Mesh m;
  m.nx = s.nodes_depth;
  m.ny = s.nodes_lateral;
  m.xs.resize(static_cast<std::size_t>(m.nx));
  for (int i = 0; i < m.nx; ++i) m.xs[static_cast<std::size_t>(i)] = s.length * i / (m.nx - 1);
  m.ys = gradedCoordinates(s.width, s.path_y, m.ny, s.grading);
  m.nodes.resize(2, m.nx * m.ny);
  for (int i = 0; i < m.nx; ++i)
    for (int j = 0; j < m.ny; ++j)
      m.nodes.col(m.node(i, j)) << m.xs[static_cast<std::size_t>(i)], m.ys[static_cast<std::size_t>(j)];
  m.quads.resize(4, (m.nx - 1) * (m.ny - 1));
  int e = 0;
  for (int i = 0; i + 1 < m.nx; ++i)
    for (int j = 0; j + 1 < m.ny; ++j)  // counter-clockwise in (x, y)
      m.quads.col(e++) << m.node(i, j), m.node(i + 1, j), m.node(i + 1, j + 1), m.node(i, j + 1);
  return m;
}

}  // namespace needlesim::realtime2d
