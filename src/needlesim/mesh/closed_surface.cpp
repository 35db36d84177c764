#include "needlesim/mesh/closed_surface.hpp"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <map>

namespace needlesim::mesh {

namespace {

using P3 = std::array<double, 3>;

P3 vertex(const TriangleSurface& s, int v) { return {s.xyz[3 * v], s.xyz[3 * v + 1], s.xyz[3 * v + 2]}; }
P3 sub(const P3& a, const P3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
P3 cross(const P3& a, const P3& b) { return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]}; }
double dot(const P3& a, const P3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

// Whether the ray p + t d (t > 0) crosses triangle k (Moller-Trumbore).
bool crosses(const TriangleSurface& s, int k, const P3& p, const P3& d) {
  const P3 a = vertex(s, s.tri[3 * k]), e1 = sub(vertex(s, s.tri[3 * k + 1]), a), e2 = sub(vertex(s, s.tri[3 * k + 2]), a);
  const P3 q = cross(d, e2);
  const double det = dot(e1, q);
  if (std::abs(det) < 1e-300) return false;
  const P3 r = sub(p, a);
  const double u = dot(r, q) / det;
  if (u < 0 || u > 1) return false;
  const P3 w = cross(r, e1);
  const double v = dot(d, w) / det;
  return v >= 0 && u + v <= 1 && dot(e2, w) / det > 0;
}

}  // namespace

std::string openEdge(const TriangleSurface& s) {
  std::map<std::pair<int, int>, int> uses;
  for (int k = 0; k < s.triangles(); ++k)
    for (int a = 0; a < 3; ++a) {
      const int i = s.tri[3 * k + a], j = s.tri[3 * k + (a + 1) % 3];
      ++uses[{std::min(i, j), std::max(i, j)}];
    }
  for (const auto& [edge, n] : uses)
    if (n != 2) {
      const P3 a = vertex(s, edge.first), b = vertex(s, edge.second);
      return fmt::format("the edge from ({:.4g}, {:.4g}, {:.4g}) to ({:.4g}, {:.4g}, {:.4g}) belongs to {} triangle{}", a[0],
                         a[1], a[2], b[0], b[1], b[2], n, n == 1 ? "" : "s");
    }
  return "";
}

double longestEdge(const TriangleSurface& s) {
  double longest = 0.0;
  for (int k = 0; k < s.triangles(); ++k)
    for (int a = 0; a < 3; ++a) {
      const P3 d = sub(vertex(s, s.tri[3 * k + a]), vertex(s, s.tri[3 * k + (a + 1) % 3]));
      longest = std::max(longest, std::sqrt(dot(d, d)));
    }
  return longest;
}

double boxDiagonal(const TriangleSurface& s) {
  P3 lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
  for (std::size_t v = 0; v < s.xyz.size() / 3; ++v)
    for (int i = 0; i < 3; ++i) {
      lo[i] = std::min(lo[i], s.xyz[3 * v + i]);
      hi[i] = std::max(hi[i], s.xyz[3 * v + i]);
    }
  const P3 d = sub(hi, lo);
  return std::sqrt(dot(d, d));
}

TriangleSurface refined(const TriangleSurface& s, double maxEdge) {
  TriangleSurface r = s;
  while (longestEdge(r) > maxEdge) {
    TriangleSurface next{r.xyz, {}};
    std::map<std::pair<int, int>, int> midpoint;
    auto mid = [&](int i, int j) {
      const auto [it, fresh] = midpoint.try_emplace({std::min(i, j), std::max(i, j)}, static_cast<int>(next.xyz.size() / 3));
      if (fresh)
        for (int c = 0; c < 3; ++c) next.xyz.push_back(0.5 * (r.xyz[3 * i + c] + r.xyz[3 * j + c]));
      return it->second;
    };
    for (int k = 0; k < r.triangles(); ++k) {
      const int a = r.tri[3 * k], b = r.tri[3 * k + 1], c = r.tri[3 * k + 2];
      const int ab = mid(a, b), bc = mid(b, c), ca = mid(c, a);
      for (int v : {a, ab, ca, ab, b, bc, ca, bc, c, ab, bc, ca}) next.tri.push_back(v);
    }
    r = std::move(next);
  }
  return r;
}

bool encloses(const TriangleSurface& s, const P3& p) {
  // an irrational direction, so that the ray misses edges and vertices of ordinary meshes
  const P3 d{0.5772156649, 0.6180339887, 0.3819660113};
  int n = 0;
  for (int k = 0; k < s.triangles(); ++k) n += crosses(s, k, p, d) ? 1 : 0;
  return n % 2 == 1;
}

Placement placement(const TriangleSurface& a, const TriangleSurface& b) {
  const std::size_t vertices = b.xyz.size() / 3, stride = std::max<std::size_t>(1, vertices / 64);
  int in = 0, out = 0;
  for (std::size_t v = 0; v < vertices; v += stride) (encloses(a, vertex(b, static_cast<int>(v))) ? in : out) += 1;
  return in > 0 && out > 0 ? Placement::Crossing : in > 0 ? Placement::Inside : Placement::Outside;
}

std::vector<std::vector<int>> directlyInside(const std::vector<TriangleSurface>& surfaces) {
  const int n = static_cast<int>(surfaces.size());
  std::vector<std::vector<char>> inside(n, std::vector<char>(n, 0));  // inside[a][b]: b lies in a
  for (int a = 0; a < n; ++a)
    for (int b = 0; b < n; ++b) inside[a][b] = a != b && placement(surfaces[a], surfaces[b]) == Placement::Inside;
  std::vector<std::vector<int>> direct(n);
  for (int a = 0; a < n; ++a)
    for (int b = 0; b < n; ++b) {
      if (!inside[a][b]) continue;
      bool between = false;
      for (int c = 0; c < n && !between; ++c) between = inside[a][c] && inside[c][b];
      if (!between) direct[a].push_back(b);
    }
  return direct;
}

}  // namespace needlesim::mesh
