#pragma once
// Small-strain static solves with the explicit solver's own element forces
// (docs/validation/fe.md, Cook's membrane and the Sneddon punch). The tangent
// stiffness at the reference state is probed by central differences of
// ExplicitSolver::internalForce (setDisplacement), perturbing all nodes of one
// distance-2 colour at once (no two of them share a neighbour, so each force
// entry comes from one perturbed node); then K_ff u_f = f - K_fp u_p is solved
// with a sparse LDL^T. Same element kernels (one-point quad4/hex8, mean
// dilatation, hourglass stiffness) as the time integration; the quasi-static
// limit of an explicit run without the cost of relaxing a nu = 0.4999 body.
#include <Eigen/Sparse>
#include <Eigen/IterativeLinearSolvers>
#include <Eigen/SparseCholesky>
#include <set>
#include <stdexcept>
#include <vector>

#include "needlesim/engines/explicit/solver.hpp"

namespace needlesim::explicit_fe::linstatic {

inline Eigen::SparseMatrix<double> probeStiffness(ExplicitSolver& s, double probe) {
  const Mesh& m = s.mesh();
  const int d = m.dim, nn = m.nodes(), npe = nodesPerElement(m.type), ne = m.elements();
  std::vector<std::vector<int>> nodeEl(nn);
  for (int e = 0; e < ne; ++e)
    for (int a = 0; a < npe; ++a) nodeEl[m.conn[e * npe + a]].push_back(e);
  auto neighbours = [&](int n) {
    std::set<int> out;
    for (int e : nodeEl[n])
      for (int a = 0; a < npe; ++a) out.insert(m.conn[e * npe + a]);
    return std::vector<int>(out.begin(), out.end());
  };
  std::vector<std::vector<int>> nb(nn);
  for (int n = 0; n < nn; ++n) nb[n] = neighbours(n);
  // greedy distance-2 colouring
  std::vector<int> colour(nn, -1);
  int ncol = 0;
  for (int n = 0; n < nn; ++n) {
    std::set<int> used;
    for (int k : nb[n])
      for (int j : nb[k])
        if (colour[j] >= 0) used.insert(colour[j]);
    int c = 0;
    while (used.count(c)) ++c;
    colour[n] = c;
    ncol = std::max(ncol, c + 1);
  }
  std::vector<Eigen::Triplet<double>> trip;
  const std::size_t ndof = static_cast<std::size_t>(nn) * d;
  std::vector<double> u(ndof, 0.0), fp, fm;
  for (int c = 0; c < ncol; ++c)
    for (int i = 0; i < d; ++i) {
      for (int n = 0; n < nn; ++n) u[n * d + i] = colour[n] == c ? probe : 0.0;
      s.setDisplacement(u);
      fp = s.internalForce();
      for (int n = 0; n < nn; ++n) u[n * d + i] = colour[n] == c ? -probe : 0.0;
      s.setDisplacement(u);
      fm = s.internalForce();
      for (int n = 0; n < nn; ++n) u[n * d + i] = 0.0;
      for (int j = 0; j < nn; ++j) {
        if (colour[j] != c) continue;
        for (int k : nb[j])
          for (int r = 0; r < d; ++r) {
            const double v = (fp[k * d + r] - fm[k * d + r]) / (2 * probe);
            if (v != 0.0) trip.emplace_back(k * d + r, j * d + i, v);
          }
      }
    }
  s.setDisplacement(std::vector<double>(ndof, 0.0));
  Eigen::SparseMatrix<double> K(static_cast<int>(ndof), static_cast<int>(ndof));
  K.setFromTriplets(trip.begin(), trip.end());
  return K;
}

// Solves K u = f with u prescribed where `fixed[k]` (value u[k] on entry). Returns u; `reaction` = K u - f.
inline std::vector<double> solveLinear(const Eigen::SparseMatrix<double>& K, const std::vector<double>& f,
                                       const std::vector<char>& fixed, std::vector<double> u,
                                       std::vector<double>* reaction = nullptr) {
  const int n = static_cast<int>(f.size());
  std::vector<int> map(n, -1);
  int nf = 0;
  for (int k = 0; k < n; ++k)
    if (!fixed[k]) map[k] = nf++;
  Eigen::VectorXd up = Eigen::VectorXd::Zero(n);
  for (int k = 0; k < n; ++k)
    if (fixed[k]) up[k] = u[k];
  Eigen::VectorXd rhs(nf);
  Eigen::VectorXd Kup = K * up;
  for (int k = 0; k < n; ++k)
    if (map[k] >= 0) rhs[map[k]] = f[k] - Kup[k];
  std::vector<Eigen::Triplet<double>> t;
  for (int c = 0; c < K.outerSize(); ++c)
    for (Eigen::SparseMatrix<double>::InnerIterator it(K, c); it; ++it)
      if (map[it.row()] >= 0 && map[it.col()] >= 0) t.emplace_back(map[it.row()], map[it.col()], it.value());
  Eigen::SparseMatrix<double> Kff(nf, nf);
  Kff.setFromTriplets(t.begin(), t.end());
  Eigen::SparseMatrix<double> Ksym = 0.5 * (Kff + Eigen::SparseMatrix<double>(Kff.transpose()));
  Eigen::VectorXd uf;
  if (nf < 20000) {  // 2D: direct
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(Ksym);
    if (ldlt.info() != Eigen::Success) throw std::runtime_error("solveLinear: factorisation failed");
    uf = ldlt.solve(rhs);
  } else {  // 3D: the direct factor fills in; Jacobi-preconditioned CG to 1e-10
    Eigen::ConjugateGradient<Eigen::SparseMatrix<double>, Eigen::Lower | Eigen::Upper> cg;
    cg.setTolerance(1e-10);
    cg.setMaxIterations(20000);
    cg.compute(Ksym);
    uf = cg.solve(rhs);
    if (cg.info() != Eigen::Success) throw std::runtime_error("solveLinear: CG did not converge");
  }
  for (int k = 0; k < n; ++k)
    if (map[k] >= 0) u[k] = uf[map[k]];
  if (reaction) {
    Eigen::VectorXd uu = Eigen::Map<Eigen::VectorXd>(u.data(), n);
    Eigen::VectorXd r = K * uu;
    reaction->assign(n, 0.0);
    for (int k = 0; k < n; ++k) (*reaction)[k] = r[k] - f[k];
  }
  return u;
}

}  // namespace needlesim::explicit_fe::linstatic
