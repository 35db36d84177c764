#include "needlesim/mesh/boundary.hpp"

#include <algorithm>
#include <cmath>
#include <map>

namespace needlesim::mesh {

namespace {

using Faces = std::vector<std::vector<int>>;

// Local node lists of each element type's facets (Gmsh node order).
const Faces& facetsOf(const std::string& element) {
  static const Faces tri3 = {{0, 1}, {1, 2}, {2, 0}};
  static const Faces quad4 = {{0, 1}, {1, 2}, {2, 3}, {3, 0}};
  static const Faces tet4 = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2}};
  static const Faces hex8 = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4}, {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}};
  if (element == "tri3") return tri3;
  if (element == "quad4") return quad4;
  if (element == "tet4") return tet4;
  return hex8;
}

Point sub(const Point& a, const Point& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
Point cross(const Point& a, const Point& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
double dot(const Point& a, const Point& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
double tetVolume(const Point& a, const Point& b, const Point& c, const Point& d) {
  return dot(sub(b, a), cross(sub(c, a), sub(d, a))) / 6.0;
}

Point centroidOf(const VolumeMesh& m, const std::vector<int>& nodes) {
  Point c{};
  for (int n : nodes) {
    const Point p = nodePoint(m, n);
    for (int i = 0; i < 3; ++i) c[i] += p[i] / static_cast<double>(nodes.size());
  }
  return c;
}

// Unit normal of a facet, pointing away from `inside`.
Point outwardNormal(const VolumeMesh& m, const std::vector<int>& nodes, const Point& inside) {
  const Point a = nodePoint(m, nodes[0]), b = nodePoint(m, nodes[1]);
  Point n = m.dim == 2 ? Point{b[1] - a[1], a[0] - b[0], 0.0}
                       : cross(sub(b, a), sub(nodePoint(m, nodes[nodes.size() - 1]), a));
  if (m.dim == 3 && nodes.size() == 4) n = cross(sub(nodePoint(m, nodes[2]), a), sub(nodePoint(m, nodes[3]), b));
  const double len = std::sqrt(dot(n, n));
  if (len > 0)
    for (double& v : n) v /= len;
  if (dot(n, sub(centroidOf(m, nodes), inside)) < 0)
    for (double& v : n) v = -v;
  return n;
}

// Ray parameter t of the crossing of from + t dir with triangle abc (Moller-Trumbore), if any.
std::optional<double> rayTriangle(const Point& from, const Point& dir, const Point& a, const Point& b,
                                  const Point& c) {
  const Point e1 = sub(b, a), e2 = sub(c, a), p = cross(dir, e2);
  const double det = dot(e1, p);
  const double scale = std::max(dot(e1, e1), dot(e2, e2));
  if (std::abs(det) <= 1e-14 * scale) return std::nullopt;  // parallel to the plane
  const Point s = sub(from, a);
  const double u = dot(s, p) / det;
  if (u < -1e-12 || u > 1 + 1e-12) return std::nullopt;
  const Point q = cross(s, e1);
  const double v = dot(dir, q) / det;
  if (v < -1e-12 || u + v > 1 + 1e-12) return std::nullopt;
  return dot(e2, q) / det;
}

// Ray parameter of the crossing of the x-y ray with segment ab, if any.
std::optional<double> raySegment(const Point& from, const Point& dir, const Point& a, const Point& b) {
  const double ex = b[0] - a[0], ey = b[1] - a[1];
  const double det = dir[0] * -ey - dir[1] * -ex;
  if (std::abs(det) <= 1e-14 * (ex * ex + ey * ey)) return std::nullopt;
  const double rx = a[0] - from[0], ry = a[1] - from[1];
  const double t = (rx * -ey - ry * -ex) / det;
  const double s = (dir[0] * ry - dir[1] * rx) / det;
  if (s < -1e-12 || s > 1 + 1e-12) return std::nullopt;
  return t;
}

}  // namespace

Point nodePoint(const VolumeMesh& m, int n) {
  Point p{};
  for (int i = 0; i < m.dim; ++i) p[i] = m.X[static_cast<std::size_t>(n) * m.dim + i];
  return p;
}

Point elementCentroid(const VolumeMesh& m, int e) {
  const int npe = m.nodesPerElement();
  std::vector<int> nodes(m.conn.begin() + static_cast<long>(e) * npe, m.conn.begin() + static_cast<long>(e + 1) * npe);
  return centroidOf(m, nodes);
}

double cornerMeasure(int dim, const std::vector<Point>& P) {
  const int npe = static_cast<int>(P.size());
  if (dim == 2) {  // shoelace
    double area = 0.0;
    for (int a = 0; a < npe; ++a) area += 0.5 * (P[a][0] * P[(a + 1) % npe][1] - P[(a + 1) % npe][0] * P[a][1]);
    return area;
  }
  if (npe == 4) return tetVolume(P[0], P[1], P[2], P[3]);
  // hexahedron: the six tetrahedra of its Kuhn split along the 0-6 diagonal
  static const int kTets[6][4] = {{0, 1, 2, 6}, {0, 5, 1, 6}, {0, 2, 3, 6}, {0, 3, 7, 6}, {0, 4, 5, 6}, {0, 7, 4, 6}};
  double v = 0.0;
  for (const auto& t : kTets) v += tetVolume(P[t[0]], P[t[1]], P[t[2]], P[t[3]]);
  return v;
}

double elementMeasure(const VolumeMesh& m, int e) {
  const int npe = m.nodesPerElement();
  std::vector<Point> corners;
  for (int a = 0; a < npe; ++a) corners.push_back(nodePoint(m, m.conn[static_cast<std::size_t>(e) * npe + a]));
  return cornerMeasure(m.dim, corners);
}

std::vector<Facet> boundaryFacets(const VolumeMesh& m) {
  const int npe = m.nodesPerElement();
  const Faces& local = facetsOf(m.element);
  std::map<std::vector<int>, std::pair<int, Facet>> seen;  // sorted nodes -> (count, facet)
  for (int e = 0; e < m.elements(); ++e)
    for (const auto& f : local) {
      Facet facet;
      facet.element = e;
      for (int a : f) facet.nodes.push_back(m.conn[static_cast<std::size_t>(e) * npe + a]);
      std::vector<int> key = facet.nodes;
      std::sort(key.begin(), key.end());
      auto [it, fresh] = seen.try_emplace(std::move(key), 0, std::move(facet));
      ++it->second.first;
    }
  std::vector<Facet> out;
  for (auto& [key, entry] : seen) {
    if (entry.first != 1) continue;
    Facet& f = entry.second;
    f.centroid = centroidOf(m, f.nodes);
    f.normal = outwardNormal(m, f.nodes, elementCentroid(m, f.element));
    out.push_back(std::move(f));
  }
  return out;
}

std::optional<double> firstCrossing(const VolumeMesh& m, const std::vector<Facet>& boundary, const Point& from,
                                    const Point& dir) {
  std::optional<double> best;
  auto consider = [&](std::optional<double> t) {
    if (t && *t >= -1e-12 && (!best || *t < *best)) best = std::max(0.0, *t);
  };
  for (const Facet& f : boundary) {
    const Point a = nodePoint(m, f.nodes[0]), b = nodePoint(m, f.nodes[1]);
    if (m.dim == 2) {
      consider(raySegment(from, dir, a, b));
      continue;
    }
    consider(rayTriangle(from, dir, a, b, nodePoint(m, f.nodes[2])));
    if (f.nodes.size() == 4) consider(rayTriangle(from, dir, a, nodePoint(m, f.nodes[2]), nodePoint(m, f.nodes[3])));
  }
  return best;
}

}  // namespace needlesim::mesh
