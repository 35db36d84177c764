#include "needlesim/engines/explicit/mesh_sleeve.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "needlesim/core/error.hpp"

namespace needlesim::explicit_fe {

namespace {
// Radial cell boundaries 0 < d_1 < ... < d_n = D: first cell h0, growing by `ratio` up to hmax, scaled to end on D.
std::vector<double> radialFractions(double D, double h0, double hmax, double ratio) {
  std::vector<double> d;
  double t = 0, h = h0;
  while (t + 1.5 * h < D) {
    t += h;
    d.push_back(t);
    h = std::min(h * ratio, hmax);
  }
  d.push_back(D);
  const double scale = 1.0 / D;
  for (double& v : d) v *= scale;
  return d;
}


void fail(const std::string& what) { throw Error("sleeve mesh: " + what); }

void checkSpec(const SleeveMeshSpec& sp) {
  if (!(sp.radius > 0)) fail("the sleeve radius must be > 0");
  if (!(sp.squareRatio > 0 && sp.squareRatio < 0.7)) fail("the inner square's half-side must lie in (0, 0.7) r_s");
  if (sp.perQuarter < 1 || sp.coreLayers < 1) fail("needs >= 1 cell per quarter circle and >= 1 core layer");
  if (sp.xs.size() < 2) fail("needs at least two axial stations");
  for (std::size_t i = 1; i < sp.xs.size(); ++i)
    if (!(sp.xs[i] > sp.xs[i - 1])) fail("axial stations must increase");
}

// The 2D cross-section (y, z relative to the axis) as an O-grid: points, quads counter-clockwise, whether
// each quad lies outside the sleeve, and the sleeve circle's point ids (ring nc).
struct Section {
  std::vector<Eigen::Vector2d> points;
  std::vector<std::array<int, 4>> quads;
  std::vector<char> outer;
  std::vector<int> circle;
};

Section crossSection(const SleeveMeshSpec& sp) {
  const int nq = sp.perQuarter, M = 4 * nq, nc = sp.coreLayers;
  const double rs = sp.radius, a = sp.squareRatio * rs;
  const double ymin = -0.5 * sp.width - sp.axisY, ymax = 0.5 * sp.width - sp.axisY;
  const double zmin = -0.5 * sp.height, zmax = 0.5 * sp.height;
  const double reach = std::min({ymax, -ymin, zmax, -zmin});
  const double hCirc = 2 * M_PI * rs / M;
  const double h0 = sp.radialSize > 0 ? sp.radialSize : hCirc;
  if (!(reach > rs + h0))
    fail("the sleeve radius " + std::to_string(rs * 1e3) + " mm plus one radial cell does not fit in the block (" +
        std::to_string(reach * 1e3) + " mm from the axis to the nearest face)");
  if (!(sp.maxSize >= h0)) fail("max element size below the first radial cell");
  const auto frac = radialFractions(reach - rs, h0, sp.maxSize, sp.grading);
  const int nOut = static_cast<int>(frac.size());

  // 2D section (coordinates relative to the axis): inner square grid, then rings
  Section sec;
  std::vector<Eigen::Vector2d>& P = sec.points;
  auto grid = [&](int i, int j) { return j * (nq + 1) + i; };
  for (int j = 0; j <= nq; ++j)
    for (int i = 0; i <= nq; ++i) P.emplace_back(-a + 2 * a * i / nq, -a + 2 * a * j / nq);
  auto squareId = [&](int k) {
    const int s = k / nq, m = k % nq;
    switch (s) {
      case 0: return grid(m, 0);
      case 1: return grid(nq, m);
      case 2: return grid(nq - m, nq);
      default: return grid(0, nq - m);
    }
  };
  const Eigen::Vector2d R[4] = {{ymin, zmin}, {ymax, zmin}, {ymax, zmax}, {ymin, zmax}};
  auto rectPoint = [&](int k) {
    const int s = k / nq;
    const double t = double(k % nq) / nq;
    return Eigen::Vector2d(R[s] + t * (R[(s + 1) % 4] - R[s]));
  };
  auto circlePoint = [&](int k) {
    const double th = -0.75 * M_PI + 2 * M_PI * k / M;
    return Eigen::Vector2d(rs * std::cos(th), rs * std::sin(th));
  };
  // ring[j][k]: j = 0 the square boundary, nc the circle, nc + nOut the block faces
  std::vector<std::vector<int>> ring(nc + nOut + 1, std::vector<int>(M));
  for (int k = 0; k < M; ++k) ring[0][k] = squareId(k);
  for (int j = 1; j <= nc + nOut; ++j)
    for (int k = 0; k < M; ++k) {
      ring[j][k] = static_cast<int>(P.size());
      const Eigen::Vector2d S = P[squareId(k)], C = circlePoint(k);
      if (j <= nc)
        P.push_back(S + (double(j) / nc) * (C - S));
      else
        P.push_back(C + frac[j - nc - 1] * (rectPoint(k) - C));
    }
  // 2D quads (counter-clockwise in y-z), outer flag
  std::vector<std::array<int, 4>>& q2 = sec.quads;
  std::vector<char>& outer = sec.outer;
  for (int j = 0; j < nq; ++j)
    for (int i = 0; i < nq; ++i) {
      q2.push_back({grid(i, j), grid(i + 1, j), grid(i + 1, j + 1), grid(i, j + 1)});
      outer.push_back(0);
    }
  for (int j = 0; j < nc + nOut; ++j)
    for (int k = 0; k < M; ++k) {
      const int k1 = (k + 1) % M;
      q2.push_back({ring[j][k], ring[j + 1][k], ring[j + 1][k1], ring[j][k1]});
      outer.push_back(j >= nc);
    }
  sec.circle = ring[nc];
  return sec;
}
}  // namespace

// Extrudes the section along x, duplicates the circle nodes down to the sleeve depth (the copies go to the
// outer elements) and lays the zero-thickness quads on the sleeve.
SleeveMesh sleeveBlock(const SleeveMeshSpec& sp) {
  checkSpec(sp);
  const Section sec = crossSection(sp);
  const auto& P = sec.points;
  const auto& q2 = sec.quads;
  const auto& outer = sec.outer;
  const int M = static_cast<int>(sec.circle.size());
  const int N2 = static_cast<int>(P.size()), nx = static_cast<int>(sp.xs.size());
  SleeveMesh out;
  Mesh& m = out.mesh;
  m.dim = 3;
  m.type = ElementType::Hex8;
  m.X.reserve(static_cast<std::size_t>(3) * (N2 * nx + M * nx));
  for (int k = 0; k < nx; ++k)
    for (int n = 0; n < N2; ++n) {
      m.X.push_back(sp.xs[k]);
      m.X.push_back(sp.axisY + P[n].x());
      m.X.push_back(P[n].y());
    }
  // copies of the circle nodes at the split stations
  const double tol = 1e-9 * std::max(1e-3, sp.xs.back() - sp.xs.front());
  std::vector<char> circle(N2, 0);
  for (int k = 0; k < M; ++k) circle[sec.circle[k]] = 1;
  std::vector<std::vector<int>> copy(nx, std::vector<int>(N2, -1));
  for (int k = 0; k < nx; ++k) {
    if (sp.xs[k] > sp.sleeveDepth + tol) continue;
    for (int c = 0; c < M; ++c) {
      const int n2 = sec.circle[c], orig = k * N2 + n2, id = m.nodes();
      m.X.push_back(m.X[3 * orig]);
      m.X.push_back(m.X[3 * orig + 1]);
      m.X.push_back(m.X[3 * orig + 2]);
      copy[k][n2] = id;
      out.pairs.emplace_back(orig, id);
    }
  }
  if (out.pairs.empty()) fail("no axial station lies within the sleeve depth");
  auto node3 = [&](int k, int n2, bool outerSide) {
    return outerSide && copy[k][n2] >= 0 ? copy[k][n2] : k * N2 + n2;
  };
  for (int k = 0; k + 1 < nx; ++k)
    for (std::size_t e = 0; e < q2.size(); ++e) {
      for (int b = 0; b < 2; ++b)
        for (int c = 0; c < 4; ++c) m.conn.push_back(node3(k + b, q2[e][c], outer[e]));
    }
  m.region.assign(m.elements(), 0);
  // zero-thickness quads on the sleeve (outer side's node ids)
  for (int k = 0; k + 1 < nx; ++k) {
    if (copy[k][sec.circle[0]] < 0) continue;  // neither station split (stations beyond the depth are never split)
    for (int c = 0; c < M; ++c) {
      const int n0 = sec.circle[c], n1 = sec.circle[(c + 1) % M];
      out.quads.push_back({node3(k, n0, true), node3(k, n1, true), node3(k + 1, n1, true), node3(k + 1, n0, true)});
      const double th = -0.75 * M_PI + 2 * M_PI * (c + 0.5) / M;
      out.quadNormals.emplace_back(0.0, std::cos(th), std::sin(th));
    }
  }
  return out;
}

}  // namespace needlesim::explicit_fe
