#include "needlesim/engines/explicit/mesh.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

#include <fmt/format.h>

#include "needlesim/core/error.hpp"
#include "needlesim/mesh/boundary.hpp"

namespace needlesim::explicit_fe {

int nodesPerElement(ElementType t) {
  switch (t) {
    case ElementType::Quad4: return 4;
    case ElementType::Tri3: return 3;
    case ElementType::Hex8: return 8;
    case ElementType::Tet4: return 4;
  }
  return 0;
}
int elementDim(ElementType t) { return (t == ElementType::Quad4 || t == ElementType::Tri3) ? 2 : 3; }
std::string elementName(ElementType t) {
  switch (t) {
    case ElementType::Quad4: return "quad4";
    case ElementType::Tri3: return "tri3";
    case ElementType::Hex8: return "hex8";
    case ElementType::Tet4: return "tet4";
  }
  return "?";
}
ElementType elementTypeFromName(const std::string& n) {
  if (n == "quad4") return ElementType::Quad4;
  if (n == "tri3") return ElementType::Tri3;
  if (n == "hex8") return ElementType::Hex8;
  if (n == "tet4") return ElementType::Tet4;
  throw Error("unknown element type '" + n + "' (allowed: quad4, tri3, hex8, tet4)");
}

namespace {
// Sizes from `len` outward: h0 * ratio^k capped at hmax, rescaled to sum to len.
std::vector<double> gradedSizes(double len, double h0, double hmax, double ratio) {
  std::vector<double> s;
  if (len <= 1e-15) return s;
  double sum = 0.0, h = h0;
  while (sum + 0.5 * h < len || s.empty()) {
    h = std::min(h * ratio, hmax);
    s.push_back(h);
    sum += h;
  }
  for (double& v : s) v *= len / sum;
  return s;
}
}  // namespace

std::vector<double> gradedCoordinates(double a, double b, double c0, double c1, double h0, double hmax,
                                      double ratio) {
  if (!(b > a) || !(h0 > 0)) throw Error("gradedCoordinates: need b > a and h0 > 0");
  hmax = std::max(hmax, h0);
  std::vector<double> x;
  if (!(c1 > c0)) {
    int n = std::max(1, static_cast<int>(std::lround((b - a) / h0)));
    for (int i = 0; i <= n; ++i) x.push_back(a + (b - a) * i / n);
    return x;
  }
  c0 = std::max(a, c0);
  c1 = std::min(b, c1);
  auto left = gradedSizes(c0 - a, h0, hmax, ratio);
  double p = c0;
  std::vector<double> lx;
  for (double s : left) lx.push_back(p -= s);
  std::reverse(lx.begin(), lx.end());
  if (!lx.empty()) lx.front() = a;
  x.insert(x.end(), lx.begin(), lx.end());
  int n = std::max(1, static_cast<int>(std::lround((c1 - c0) / h0)));
  for (int i = 0; i <= n; ++i) x.push_back(c0 + (c1 - c0) * i / n);
  p = c1;
  for (double s : gradedSizes(b - c1, h0, hmax, ratio)) x.push_back(p += s);
  x.back() = std::max(x.back(), b);
  if (b - c1 > 1e-15) x.back() = b;
  return x;
}

Mesh structuredBlock(const std::vector<double>& xs, const std::vector<double>& ys, ElementType type) {
  if (type != ElementType::Quad4 && type != ElementType::Tri3)
    throw Error("structuredBlock 2D: element type must be quad4 or tri3");
  Mesh m;
  m.dim = 2;
  m.type = type;
  const int nx = static_cast<int>(xs.size()), ny = static_cast<int>(ys.size());
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      m.X.push_back(xs[i]);
      m.X.push_back(ys[j]);
    }
  auto id = [&](int i, int j) { return j * nx + i; };
  for (int j = 0; j + 1 < ny; ++j)
    for (int i = 0; i + 1 < nx; ++i) {
      int n0 = id(i, j), n1 = id(i + 1, j), n2 = id(i + 1, j + 1), n3 = id(i, j + 1);
      if (type == ElementType::Quad4) {
        m.conn.insert(m.conn.end(), {n0, n1, n2, n3});
        m.region.push_back(0);
      } else if ((i + j) % 2 == 0) {
        m.conn.insert(m.conn.end(), {n0, n1, n2, n0, n2, n3});
        m.region.insert(m.region.end(), {0, 0});
      } else {
        m.conn.insert(m.conn.end(), {n0, n1, n3, n1, n2, n3});
        m.region.insert(m.region.end(), {0, 0});
      }
    }
  return m;
}

Mesh structuredBlock(const std::vector<double>& xs, const std::vector<double>& ys,
                     const std::vector<double>& zs, ElementType type) {
  if (type != ElementType::Hex8 && type != ElementType::Tet4)
    throw Error("structuredBlock 3D: element type must be hex8 or tet4");
  Mesh m;
  m.dim = 3;
  m.type = type;
  const int nx = static_cast<int>(xs.size()), ny = static_cast<int>(ys.size()),
            nz = static_cast<int>(zs.size());
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) m.X.insert(m.X.end(), {xs[i], ys[j], zs[k]});
  auto id = [&](int i, int j, int k) { return (k * ny + j) * nx + i; };
  // Kuhn (Freudenthal) split along the 0-6 diagonal: conforming on a structured grid.
  static const int kTets[6][4] = {{0, 1, 2, 6}, {0, 5, 1, 6}, {0, 2, 3, 6},
                                  {0, 3, 7, 6}, {0, 4, 5, 6}, {0, 7, 4, 6}};
  for (int k = 0; k + 1 < nz; ++k)
    for (int j = 0; j + 1 < ny; ++j)
      for (int i = 0; i + 1 < nx; ++i) {
        int h[8] = {id(i, j, k),     id(i + 1, j, k),     id(i + 1, j + 1, k),     id(i, j + 1, k),
                    id(i, j, k + 1), id(i + 1, j, k + 1), id(i + 1, j + 1, k + 1), id(i, j + 1, k + 1)};
        if (type == ElementType::Hex8) {
          m.conn.insert(m.conn.end(), h, h + 8);
          m.region.push_back(0);
          continue;
        }
        for (auto& t : kTets) {
          int a = h[t[0]], b = h[t[1]], c = h[t[2]], d = h[t[3]];
          auto P = [&](int n, int q) { return m.X[3 * n + q]; };
          double e1[3], e2[3], e3[3];
          for (int q = 0; q < 3; ++q) {
            e1[q] = P(b, q) - P(a, q);
            e2[q] = P(c, q) - P(a, q);
            e3[q] = P(d, q) - P(a, q);
          }
          double vol = e1[0] * (e2[1] * e3[2] - e2[2] * e3[1]) - e1[1] * (e2[0] * e3[2] - e2[2] * e3[0]) +
                       e1[2] * (e2[0] * e3[1] - e2[1] * e3[0]);
          if (vol < 0) std::swap(b, c);
          m.conn.insert(m.conn.end(), {a, b, c, d});
          m.region.push_back(0);
        }
      }
  return m;
}

void snapCoordinate(std::vector<double>& xs, double value) {
  std::size_t best = 0;
  for (std::size_t i = 1; i < xs.size(); ++i)
    if (std::abs(xs[i] - value) < std::abs(xs[best] - value)) best = i;
  if (best == 0 || best + 1 == xs.size()) return;  // never move the block faces
  xs[best] = value;
}

std::vector<std::pair<int, int>> splitSeam(Mesh& m, double offset, double x0, double x1, double halfWidth) {
  const int d = m.dim, npe = nodesPerElement(m.type), n0 = m.nodes();
  double tol = 1e-9;
  for (std::size_t k = 1; k < m.X.size() / d; ++k) tol = std::max(tol, 0.0);
  std::vector<int> copyOf(n0, -1);
  std::vector<std::pair<int, int>> pairs;
  auto onSeam = [&](int n) {
    double x = m.coord(n, 0), y = m.coord(n, 1);
    if (std::abs(y - offset) > 1e-9 || x < x0 - 1e-12 || x > x1 + 1e-12) return false;
    if (d == 3 && std::abs(m.coord(n, 2)) >= halfWidth - 1e-12) return false;
    return true;
  };
  for (int n = 0; n < n0; ++n)
    if (onSeam(n)) {
      copyOf[n] = m.nodes();
      for (int i = 0; i < d; ++i) m.X.push_back(m.coord(n, i));
      pairs.emplace_back(n, copyOf[n]);
    }
  for (int e = 0; e < m.elements(); ++e) {
    double cy = 0;
    for (int a = 0; a < npe; ++a) cy += m.coord(m.conn[e * npe + a], 1) / npe;
    if (cy <= offset) continue;
    for (int a = 0; a < npe; ++a) {
      int& n = m.conn[e * npe + a];
      if (copyOf[n] >= 0) n = copyOf[n];
    }
  }
  return pairs;
}

namespace {

// Signed area (2D) or volume (3D) of element e (mesh/boundary.hpp cornerMeasure).
double signedMeasure(const Mesh& m, int e) {
  const int npe = nodesPerElement(m.type);
  std::vector<mesh::Point> corners(npe, mesh::Point{});
  for (int a = 0; a < npe; ++a)
    for (int i = 0; i < m.dim; ++i) corners[a][i] = m.coord(m.conn[static_cast<std::size_t>(e) * npe + a], i);
  return mesh::cornerMeasure(m.dim, corners);
}

// The nodes of an element pair that straddles the seam window, the one nearer the seam first;
// {-1, -1} if it does not straddle it.
std::pair<int, int> nodesToSnap(const Mesh& m, int a, int b, double offset, double x0, double x1, double halfWidth) {
  const double da = m.coord(a, 1) - offset, db = m.coord(b, 1) - offset;
  const double scale = 1e-12 * (std::abs(da) + std::abs(db));
  const std::pair<int, int> none{-1, -1};
  if (!((da > scale && db < -scale) || (da < -scale && db > scale))) return none;
  const double s = da / (da - db);  // where the segment meets the seam
  const double x = m.coord(a, 0) + s * (m.coord(b, 0) - m.coord(a, 0));
  if (x < x0 || x > x1) return none;
  if (m.dim == 3 && std::abs(m.coord(a, 2) + s * (m.coord(b, 2) - m.coord(a, 2))) >= halfWidth) return none;
  return std::abs(da) <= std::abs(db) ? std::pair{a, b} : std::pair{b, a};
}

// The elements of each node.
std::vector<std::vector<int>> elementsOfNodes(const Mesh& m) {
  const int npe = nodesPerElement(m.type);
  std::vector<std::vector<int>> of(m.nodes());
  for (int e = 0; e < m.elements(); ++e)
    for (int a = 0; a < npe; ++a) of[m.conn[e * npe + a]].push_back(e);
  return of;
}

// Moves node n onto y = offset unless that leaves one of its elements with under a tenth of its
// measure (or turns it round); returns whether it moved.
bool snapIfSafe(Mesh& m, int n, double offset, const std::vector<int>& elements, const std::vector<double>& before) {
  const double y = m.X[static_cast<std::size_t>(n) * m.dim + 1];
  m.X[static_cast<std::size_t>(n) * m.dim + 1] = offset;
  for (int e : elements)
    if (signedMeasure(m, e) * (before[e] < 0 ? -1.0 : 1.0) < 0.1 * std::abs(before[e])) {
      m.X[static_cast<std::size_t>(n) * m.dim + 1] = y;
      return false;
    }
  return true;
}

}  // namespace

int snapOntoSeam(Mesh& m, double offset, double x0, double x1, double halfWidth) {
  const int npe = nodesPerElement(m.type);
  std::vector<double> before(m.elements());
  for (int e = 0; e < m.elements(); ++e) before[e] = signedMeasure(m, e);
  const auto elementsOf = elementsOfNodes(m);
  std::vector<char> moved(m.nodes(), 0), refused(m.nodes(), 0);
  int count = 0;
  for (bool again = true; again;) {
    again = false;
    for (int e = 0; e < m.elements(); ++e)
      for (int i = 0; i < npe; ++i)
        for (int j = i + 1; j < npe; ++j) {
          const auto [near, far] = nodesToSnap(m, m.conn[e * npe + i], m.conn[e * npe + j], offset, x0, x1, halfWidth);
          if (near < 0) continue;
          for (int n : {near, far}) {  // the farther node when the nearer cannot move
            if (refused[n]) continue;
            if (!snapIfSafe(m, n, offset, elementsOf[n], before)) {
              refused[n] = 1;
              continue;
            }
            count += moved[n] ? 0 : 1;
            moved[n] = 1;
            again = true;
            break;
          }
        }
  }
  return count;
}

std::vector<std::pair<int, int>> splitAlongFaces(Mesh& m, double offset, double x0, double x1, double halfWidth,
                                                 int needleSide) {
  const int d = m.dim, npe = nodesPerElement(m.type), n0 = m.nodes();
  std::vector<char> plus(m.elements(), 0), onPlus(n0, 0), onMinus(n0, 0);
  for (int e = 0; e < m.elements(); ++e) {
    bool reaches = false;  // a node strictly on the needle's side
    for (int a = 0; a < npe; ++a) reaches = reaches || needleSide * (m.coord(m.conn[e * npe + a], 1) - offset) > 1e-12;
    plus[e] = needleSide > 0 ? reaches : !reaches;
    for (int a = 0; a < npe; ++a) (plus[e] ? onPlus : onMinus)[m.conn[e * npe + a]] = 1;
  }
  std::vector<int> copyOf(n0, -1);
  std::vector<std::pair<int, int>> pairs;
  for (int n = 0; n < n0; ++n) {
    const double x = m.coord(n, 0);
    if (!onPlus[n] || !onMinus[n] || x < x0 - 1e-12 || x > x1 + 1e-12) continue;
    if (d == 3 && std::abs(m.coord(n, 2)) >= halfWidth - 1e-12) continue;
    copyOf[n] = m.nodes();
    for (int i = 0; i < d; ++i) m.X.push_back(m.coord(n, i));
    pairs.emplace_back(n, copyOf[n]);
  }
  for (int e = 0; e < m.elements(); ++e)
    if (plus[e])
      for (int a = 0; a < npe; ++a) {
        int& n = m.conn[e * npe + a];
        if (copyOf[n] >= 0) n = copyOf[n];
      }
  return pairs;
}

double largestEdgeAcross(const Mesh& m, double offset, double halfWidth) {
  const int npe = nodesPerElement(m.type);
  double longest = 0.0;
  for (int e = 0; e < m.elements(); ++e) {
    const int* c = &m.conn[static_cast<std::size_t>(e) * npe];
    double lo = 1e300, hi = -1e300, zmin = 1e300;
    for (int a = 0; a < npe; ++a) {
      lo = std::min(lo, m.coord(c[a], 1));
      hi = std::max(hi, m.coord(c[a], 1));
      zmin = std::min(zmin, std::abs(m.coord(c[a], 2)));
    }
    if (lo > offset || hi < offset || zmin >= halfWidth) continue;
    for (int a = 0; a < npe; ++a)
      for (int b = a + 1; b < npe; ++b) {
        double d2 = 0.0;
        for (int i = 0; i < m.dim; ++i) d2 += std::pow(m.coord(c[a], i) - m.coord(c[b], i), 2);
        longest = std::max(longest, std::sqrt(d2));
      }
  }
  return longest;
}

Mesh fromImportedGeometry(const ImportedGeometry& g) {
  Mesh m = fromVolumeMesh(*g.mesh);
  m.region = g.region;
  return m;
}

Mesh fromVolumeMesh(const mesh::VolumeMesh& v) {
  Mesh m;
  m.dim = v.dim;
  m.type = elementTypeFromName(v.element);
  m.X = v.X;
  m.conn = v.conn;
  std::map<int, int> regionOf;  // tag -> region, in increasing tag order
  for (int t : v.tag) regionOf.emplace(t, 0);
  int r = 0;
  for (auto& kv : regionOf) kv.second = r++;
  m.region.reserve(v.tag.size());
  for (int t : v.tag) m.region.push_back(regionOf[t]);
  return m;
}

}  // namespace needlesim::explicit_fe
