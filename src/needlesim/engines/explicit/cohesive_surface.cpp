// 3D zero-thickness cohesive quadrilaterals on a seam plane of a hex8 mesh
// (docs/models/cohesive.md "Interface (3D)"). Seed 001 section 3.3 inserts
// cohesive elements along the needle path in its hexahedral mesh; the law is
// the bilinear one of cohesive.cpp (seed 001 eqs 5-6, seed 004 eq 14) with an
// isotropic shear separation (delta_s = |delta - delta_n n|). Nodal
// (Newton-Cotes) integration: no spurious traction oscillations in a stiff
// interface (Schellekens & de Borst 1993), and each node pair is one
// integration point, so damage and opening are per pair as in 2D.
#include <Eigen/Geometry>
#include <cmath>
#include <string>

#include "needlesim/core/error.hpp"
#include "needlesim/engines/explicit/cohesive.hpp"
#include "needlesim/engines/explicit/mesh.hpp"

namespace needlesim::explicit_fe {

namespace {
// hex8 faces in cyclic order (0-3 bottom, 4-7 top, structuredBlock / Gmsh numbering)
constexpr int kHexFaces[6][4] = {{0, 1, 2, 3}, {4, 5, 6, 7}, {0, 1, 5, 4}, {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}};
}  // namespace

CohesiveInterface CohesiveInterface::surface3D(const Mesh& m, const std::vector<std::pair<int, int>>& pairs,
                                               std::vector<CohesiveLaw> laws, Eigen::Vector3d refNormal,
                                               Eigen::Vector3d direction) {
  if (m.dim != 3 || m.type != ElementType::Hex8)
    throw Error("cohesive interface 3D: needs a hex8 mesh (quadrilateral faces on the seam plane)");
  if (pairs.empty()) throw Error("cohesive interface 3D: no seam pairs");
  refNormal.normalize();
  auto P = [&](int n) { return Eigen::Vector3d(m.X[3 * n], m.X[3 * n + 1], m.X[3 * n + 2]); };
  const Eigen::Vector3d dir = direction.normalized();
  std::vector<char> isCopy(m.nodes(), 0), split(m.nodes(), 0);
  for (const auto& [a, b] : pairs) {
    isCopy[b] = 1;
    split[a] = split[b] = 1;
  }
  const double plane = P(pairs[0].first).dot(refNormal);
  double size = 0;  // length scale for the plane tolerance
  for (const auto& pr : pairs) size = std::max(size, std::abs((P(pr.first) - P(pairs[0].first)).dot(dir)));
  const double tol = 1e-9 * std::max(size, 1e-3);
  std::vector<std::array<int, 4>> quads;
  for (int e = 0; e < m.elements(); ++e) {
    const int* h = &m.conn[8 * e];
    Eigen::Vector3d cen = Eigen::Vector3d::Zero();
    for (int a = 0; a < 8; ++a) cen += P(h[a]) / 8;
    if ((cen.dot(refNormal) - plane) <= 0) continue;  // the copies belong to the + side
    for (const auto& fc : kHexFaces) {
      std::array<int, 4> q{};
      bool onPlane = true, anyCopy = false;
      for (int k = 0; k < 4; ++k) {
        const int n = h[fc[k]];
        // off the plane, or an original a of a pair on the + side: not this seam's face
        if (std::abs(P(n).dot(refNormal) - plane) > tol || (split[n] && !isCopy[n])) {
          onPlane = false;
          break;
        }
        q[k] = n;
        anyCopy = anyCopy || isCopy[n];
      }
      if (onPlane && anyCopy) quads.push_back(q);
    }
  }
  if (quads.empty()) throw Error("cohesive interface 3D: no hex face lies on the seam plane");
  return fromQuads(m, pairs, std::move(laws), quads, std::vector<Eigen::Vector3d>(quads.size(), refNormal), dir);
}

CohesiveInterface CohesiveInterface::fromQuads(const Mesh& m, const std::vector<std::pair<int, int>>& pairs,
                                               std::vector<CohesiveLaw> laws,
                                               const std::vector<std::array<int, 4>>& quadNodes,
                                               const std::vector<Eigen::Vector3d>& quadRefNormals,
                                               Eigen::Vector3d direction) {
  if (m.dim != 3) throw Error("cohesive interface 3D: needs a 3D mesh");
  if (laws.size() != 1 && laws.size() != pairs.size())
    throw Error("cohesive interface: one law per pair or one for all");
  if (pairs.empty()) throw Error("cohesive interface 3D: no seam pairs");
  if (quadNodes.empty() || quadNodes.size() != quadRefNormals.size())
    throw Error("cohesive interface 3D: no quadrilaterals, or not one reference normal per quadrilateral");
  for (const auto& l : laws) l.validate();
  CohesiveInterface c;
  c.dim_ = 3;
  c.refNormal3_ = quadRefNormals.front().normalized();
  const Eigen::Vector3d dir = direction.normalized();
  auto P = [&](int n) { return Eigen::Vector3d(m.X[3 * n], m.X[3 * n + 1], m.X[3 * n + 2]); };
  const int np = static_cast<int>(pairs.size());
  std::vector<int> pairOfCopy(m.nodes(), -1);
  std::vector<char> split(m.nodes(), 0);
  for (int p = 0; p < np; ++p) {
    pairOfCopy[pairs[p].second] = p;
    split[pairs[p].first] = split[pairs[p].second] = 1;
    c.a_.push_back(pairs[p].first);
    c.b_.push_back(pairs[p].second);
    c.s_.push_back(P(pairs[p].first).dot(dir));
    c.law_.push_back(laws.size() == 1 ? laws[0] : laws[p]);
  }
  c.len_.assign(np, 0.0);
  for (std::size_t f = 0; f < quadNodes.size(); ++f) {
    std::array<int, 4> q{};
    Eigen::Vector3d x[4];
    for (int k = 0; k < 4; ++k) {
      const int n = quadNodes[f][k];
      if (n < 0 || n >= m.nodes()) throw Error("cohesive interface 3D: quadrilateral node out of range");
      if (split[n] && pairOfCopy[n] < 0)
        throw Error("cohesive interface 3D: quadrilateral " + std::to_string(f) + " lists the core-side node " +
                    std::to_string(n) + " of a pair (give the copy)");
      q[k] = pairOfCopy[n] >= 0 ? pairOfCopy[n] : -1 - n;  // unsplit node: closed crack front
      x[k] = P(n);
    }
    // reference weights int N_a dA (2x2 Gauss on the bilinear face)
    const double g = 1.0 / std::sqrt(3.0);
    const double xi[4] = {-1, 1, 1, -1}, eta[4] = {-1, -1, 1, 1};
    double w[4] = {0, 0, 0, 0};
    for (double gx : {-g, g})
      for (double gy : {-g, g}) {
        Eigen::Vector3d dxi = Eigen::Vector3d::Zero(), deta = Eigen::Vector3d::Zero();
        for (int k = 0; k < 4; ++k) {
          dxi += 0.25 * xi[k] * (1 + eta[k] * gy) * x[k];
          deta += 0.25 * eta[k] * (1 + xi[k] * gx) * x[k];
        }
        const double J = dxi.cross(deta).norm();
        for (int k = 0; k < 4; ++k) w[k] += 0.25 * (1 + xi[k] * gx) * (1 + eta[k] * gy) * J;
      }
    for (int k = 0; k < 4; ++k)
      if (q[k] >= 0) c.len_[q[k]] += w[k];
    const Eigen::Vector3d nref = (x[2] - x[0]).cross(x[3] - x[1]);
    c.quad_.push_back(q);
    c.quadSign_.push_back(nref.dot(quadRefNormals[f]) >= 0 ? 1.0 : -1.0);
  }
  for (int p = 0; p < np; ++p)
    if (!(c.len_[p] > 0))
      throw Error("cohesive interface 3D: seam pair " + std::to_string(p) + " (node " + std::to_string(c.a_[p]) +
                  ") belongs to no face on the seam");
  // pair -> quads (CSR)
  c.pairQuadStart_.assign(np + 1, 0);
  for (const auto& q : c.quad_)
    for (int k : q)
      if (k >= 0) ++c.pairQuadStart_[k + 1];
  for (int p = 0; p < np; ++p) c.pairQuadStart_[p + 1] += c.pairQuadStart_[p];
  c.pairQuads_.assign(c.pairQuadStart_[np], 0);
  std::vector<int> fill(c.pairQuadStart_.begin(), c.pairQuadStart_.end() - 1);
  for (int f = 0; f < static_cast<int>(c.quad_.size()); ++f)
    for (int k : c.quad_[f])
      if (k >= 0) c.pairQuads_[fill[k]++] = f;
  c.quadNormal_.assign(3 * c.quad_.size(), 0.0);
  c.st_.assign(np, CohesiveState{});
  c.psi_.assign(np, 0.0);
  c.dn_.assign(np, 0.0);
  c.w_ = 1.0;
  return c;
}

void CohesiveInterface::addForces3D(const std::vector<double>& X, const std::vector<double>& u,
                                    std::vector<double>& f) {
  auto xOf = [&](int n) {
    return Eigen::Vector3d(X[3 * n] + u[3 * n], X[3 * n + 1] + u[3 * n + 1], X[3 * n + 2] + u[3 * n + 2]);
  };
  auto mid = [&](int k) { return k >= 0 ? Eigen::Vector3d(0.5 * (xOf(a_[k]) + xOf(b_[k]))) : xOf(-1 - k); };
  const int nq = quads();
  // current mid-surface normal of each quad (diagonal cross product: 2 x area x normal)
#pragma omp parallel for schedule(static) if (nq >= 2048)
  for (int q = 0; q < nq; ++q) {
    const auto& c = quad_[q];
    const Eigen::Vector3d nq3 = quadSign_[q] * (mid(c[2]) - mid(c[0])).cross(mid(c[3]) - mid(c[1]));
    for (int i = 0; i < 3; ++i) quadNormal_[3 * q + i] = nq3[i];
  }
  const int n = pairs();
  double stored = 0, diss = 0;
#pragma omp parallel for schedule(static) if (n >= 2048) reduction(+ : stored, diss)
  for (int p = 0; p < n; ++p) {
    Eigen::Vector3d nrm = Eigen::Vector3d::Zero();
    for (int k = pairQuadStart_[p]; k < pairQuadStart_[p + 1]; ++k)
      nrm += Eigen::Vector3d(&quadNormal_[3 * pairQuads_[k]]);
    const double nl = nrm.norm();
    nrm = nl > 0 && std::isfinite(nl) ? Eigen::Vector3d(nrm / nl) : refNormal3_;
    const int a = a_[p], b = b_[p];
    const Eigen::Vector3d delta = xOf(b) - xOf(a);
    const double dn = delta.dot(nrm);
    const Eigen::Vector3d dsv = delta - dn * nrm;
    const double ds = dsv.norm();
    dn_[p] = dn;
    const CohesiveTraction t = cohesiveUpdate(law_[p], dn, ds, st_[p]);
    Eigen::Vector3d F = t.tn * nrm;
    if (ds > 0) F += (t.ts / ds) * dsv;  // isotropic shear along the tangential separation
    F *= len_[p];
    for (int i = 0; i < 3; ++i) {
      f[3 * a + i] += F[i];
      f[3 * b + i] -= F[i];
    }
    psi_[p] = t.stored;
    stored += t.stored * len_[p];
    diss += st_[p].dissipated * len_[p];
  }
  stored_ = stored;
  dissipated_ = diss;
}

}  // namespace needlesim::explicit_fe
