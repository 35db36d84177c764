#include "needlesim/engines/explicit/mesh.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <sstream>

#include "needlesim/core/error.hpp"

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

Mesh readGmsh(const std::string& path) {
  std::ifstream in(path);
  SourceLocation where{path, 0, 0};
  if (!in) throw InputError(where, "mesh", path, "cannot open the Gmsh file", "a readable .msh file");
  std::string tok;
  std::map<std::pair<int, int>, int> physical;  // (dim, entity) -> physical tag
  std::map<long, int> nodeIndex;
  std::vector<double> X3;
  struct Block {
    int dim, entity, type;
    std::vector<long> conn;
  };
  std::vector<Block> blocks;
  bool formatOk = false;
  while (in >> tok) {
    if (tok == "$MeshFormat") {
      double ver;
      int ft, ds;
      in >> ver >> ft >> ds;
      if (ver < 4.0 || ft != 0)
        throw InputError(where, "$MeshFormat", std::to_string(ver), "unsupported Gmsh format",
                         "format 4.1 ASCII (gmsh -format msh41)");
      formatOk = true;
    } else if (tok == "$Entities") {
      std::size_t n[4];
      in >> n[0] >> n[1] >> n[2] >> n[3];
      for (int d = 0; d < 4; ++d)
        for (std::size_t e = 0; e < n[d]; ++e) {
          int tag;
          double b;
          in >> tag;
          for (int q = 0; q < (d == 0 ? 3 : 6); ++q) in >> b;
          std::size_t np;
          in >> np;
          for (std::size_t p = 0; p < np; ++p) {
            int ph;
            in >> ph;
            if (p == 0) physical[{d, tag}] = ph;
          }
          if (d > 0) {
            std::size_t nb;
            in >> nb;
            for (std::size_t p = 0; p < nb; ++p) in >> b;
          }
        }
    } else if (tok == "$Nodes") {
      std::size_t nb, nn, mn, mx;
      in >> nb >> nn >> mn >> mx;
      for (std::size_t b = 0; b < nb; ++b) {
        int ed, et, par;
        std::size_t cnt;
        in >> ed >> et >> par >> cnt;
        std::vector<long> tags(cnt);
        for (auto& t : tags) in >> t;
        for (std::size_t i = 0; i < cnt; ++i) {
          double x, y, z;
          in >> x >> y >> z;
          for (int p = 0; p < par * ed; ++p) in >> tok;
          nodeIndex[tags[i]] = static_cast<int>(X3.size() / 3);
          X3.insert(X3.end(), {x, y, z});
        }
      }
    } else if (tok == "$Elements") {
      std::size_t nb, ne, mn, mx;
      in >> nb >> ne >> mn >> mx;
      for (std::size_t b = 0; b < nb; ++b) {
        Block bl;
        std::size_t cnt;
        in >> bl.dim >> bl.entity >> bl.type >> cnt;
        static const std::map<int, int> npe{{1, 2}, {2, 3}, {3, 4}, {4, 4}, {5, 8}, {15, 1}};
        auto it = npe.find(bl.type);
        if (it == npe.end())
          throw InputError(where, "$Elements", std::to_string(bl.type), "unsupported Gmsh element type",
                           "first-order points, lines, triangles (2), quads (3), tets (4), hexes (5)");
        for (std::size_t i = 0; i < cnt; ++i) {
          long t;
          in >> t;
          for (int q = 0; q < it->second; ++q) {
            in >> t;
            bl.conn.push_back(t);
          }
        }
        blocks.push_back(std::move(bl));
      }
    }
  }
  if (!formatOk || X3.empty())
    throw InputError(where, "mesh", path, "no $MeshFormat or no $Nodes section", "a Gmsh 4.1 ASCII mesh");
  int topDim = 0;
  for (auto& b : blocks) topDim = std::max(topDim, b.dim);
  int type = -1;
  for (auto& b : blocks)
    if (b.dim == topDim) {
      if (type >= 0 && b.type != type)
        throw InputError(where, "$Elements", std::to_string(b.type), "mixed element types in one mesh",
                         "one element type of the highest dimension");
      type = b.type;
    }
  if (topDim < 2 || type < 0)
    throw InputError(where, "$Elements", "", "no 2D or 3D elements", "triangles, quads, tets or hexes");
  Mesh m;
  m.dim = topDim;
  m.type = type == 2 ? ElementType::Tri3 : type == 3 ? ElementType::Quad4 : type == 4 ? ElementType::Tet4
                                                                                      : ElementType::Hex8;
  for (std::size_t i = 0; i < X3.size() / 3; ++i)
    for (int q = 0; q < m.dim; ++q) m.X.push_back(X3[3 * i + q]);
  std::map<int, int> regionOf;
  for (auto& b : blocks)
    if (b.dim == topDim) {
      auto it = physical.find({b.dim, b.entity});
      regionOf.emplace(it == physical.end() ? b.entity : it->second, 0);
    }
  int r = 0;
  for (auto& kv : regionOf) kv.second = r++;
  for (auto& b : blocks) {
    if (b.dim != topDim) continue;
    auto it = physical.find({b.dim, b.entity});
    int reg = regionOf[it == physical.end() ? b.entity : it->second];
    for (long t : b.conn) {
      auto n = nodeIndex.find(t);
      if (n == nodeIndex.end())
        throw InputError(where, "$Elements", std::to_string(t), "element refers to an unknown node", "");
      m.conn.push_back(n->second);
    }
    for (std::size_t e = 0; e < b.conn.size() / nodesPerElement(m.type); ++e) m.region.push_back(reg);
  }
  return m;
}

}  // namespace needlesim::explicit_fe
