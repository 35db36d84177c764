// Tissue FE and Newmark of the real-time 2D engine (seed 003 eqs 3.1-3.15).
#include <gtest/gtest.h>

#include <Eigen/SparseCholesky>
#include <cmath>

#include "needlesim/engines/realtime2d/fe.hpp"
#include "needlesim/engines/realtime2d/tissue.hpp"

using namespace needlesim::realtime2d;

namespace {
// Solves K u = f with prescribed values on `held` DOFs.
Eigen::VectorXd solvePrescribed(const Eigen::SparseMatrix<double>& K, const std::vector<bool>& held,
                                const Eigen::VectorXd& uPresc, const Eigen::VectorXd& f) {
  const auto map = makeDofMap(static_cast<int>(K.rows()), held);
  const Eigen::VectorXd r = f - K * uPresc;  // uPresc is zero on free DOFs
  Eigen::VectorXd rf(map.freeCount());
  for (int k = 0; k < map.freeCount(); ++k) rf[k] = r[map.dof_of_free[static_cast<std::size_t>(k)]];
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> s(restrictToFree(K, map));
  const Eigen::VectorXd uf = s.solve(rf);
  Eigen::VectorXd u = uPresc;
  for (int k = 0; k < map.freeCount(); ++k) u[map.dof_of_free[static_cast<std::size_t>(k)]] = uf[k];
  return u;
}
MeshSpec gradedSpec(int nx, int ny) {
  MeshSpec s;
  s.length = 0.08; s.width = 0.12; s.nodes_depth = nx; s.nodes_lateral = ny; s.path_y = 0.05; s.grading = 4.0;
  return s;
}
}  // namespace

// Patch test: a linear displacement field imposed on the boundary of a graded
// (non-uniform) mesh is reproduced exactly inside, with the exact constant stress.
TEST(Realtime2dFe, PatchTestLinearFieldIsExact) {
  const Mesh mesh = generateMesh(gradedSpec(7, 9));
  ElasticMaterial mat;
  const auto as = assemble(mesh, mat, false);
  const int N = mesh.nodeCount();
  auto exact = [](const Eigen::Vector2d& p) {
    return Eigen::Vector2d(1e-4 + 2e-3 * p.x() - 1e-3 * p.y(), -2e-4 + 5e-4 * p.x() + 3e-3 * p.y());
  };
  std::vector<bool> held(static_cast<std::size_t>(2 * N), false);
  Eigen::VectorXd up = Eigen::VectorXd::Zero(2 * N);
  for (int i = 0; i < mesh.nx; ++i)
    for (int j = 0; j < mesh.ny; ++j)
      if (i == 0 || j == 0 || i == mesh.nx - 1 || j == mesh.ny - 1) {
        const int n = mesh.node(i, j);
        held[static_cast<std::size_t>(2 * n)] = held[static_cast<std::size_t>(2 * n + 1)] = true;
        up.segment<2>(2 * n) = exact(mesh.nodes.col(n));
      }
  const Eigen::VectorXd u = solvePrescribed(as.K, held, up, Eigen::VectorXd::Zero(2 * N));
  for (int n = 0; n < N; ++n) EXPECT_NEAR((u.segment<2>(2 * n) - exact(mesh.nodes.col(n))).norm(), 0.0, 1e-12);
  // Constant strain (2e-3, 3e-3, -1e-3 + 5e-4) -> stress D eps in every element.
  const Eigen::Matrix3d D = elasticity(mat);
  const Eigen::Vector3d sig = D * Eigen::Vector3d(2e-3, 3e-3, -5e-4);
  for (int e = 0; e < mesh.elementCount(); ++e) {
    Eigen::Matrix<double, 2, 4> xy;
    Eigen::Matrix<double, 8, 1> ue;
    for (int a = 0; a < 4; ++a) {
      xy.col(a) = mesh.nodes.col(mesh.quads(a, e));
      ue.segment<2>(2 * a) = u.segment<2>(2 * mesh.quads(a, e));
    }
    EXPECT_LT((quadCentreStress(xy, D, ue) - sig).norm(), 1e-9 * sig.norm());
  }
}

// Plate on rollers (x = 0 and y = 0) under uniform traction p on x = L: the
// closed form u_x = p x / E', u_y = -nu' p y / E' (plane stress E' = E, nu' = nu;
// plane strain E' = E / (1 - nu^2), nu' = nu / (1 - nu)) is reproduced exactly.
TEST(Realtime2dFe, PlateUnderUniformTractionMatchesClosedForm) {
  for (bool planeStrain : {false, true}) {
    const Mesh mesh = generateMesh(gradedSpec(6, 7));
    ElasticMaterial mat;
    mat.plane_strain = planeStrain;
    const auto as = assemble(mesh, mat, true);
    const int N = mesh.nodeCount();
    const double p = 150.0;  // Pa
    std::vector<bool> held(static_cast<std::size_t>(2 * N), false);
    Eigen::VectorXd f = Eigen::VectorXd::Zero(2 * N);
    for (int j = 0; j < mesh.ny; ++j) {
      held[static_cast<std::size_t>(2 * mesh.node(0, j))] = true;  // u_x = 0 on x = 0
      const double lo = j > 0 ? mesh.ys[static_cast<std::size_t>(j)] - mesh.ys[static_cast<std::size_t>(j - 1)] : 0.0;
      const double hi = j + 1 < mesh.ny ? mesh.ys[static_cast<std::size_t>(j + 1)] - mesh.ys[static_cast<std::size_t>(j)] : 0.0;
      f[2 * mesh.node(mesh.nx - 1, j)] = p * mat.thickness * 0.5 * (lo + hi);  // consistent edge load
    }
    for (int i = 0; i < mesh.nx; ++i) held[static_cast<std::size_t>(2 * mesh.node(i, 0) + 1)] = true;  // u_y = 0 on y = 0
    const Eigen::VectorXd u = solvePrescribed(as.K, held, Eigen::VectorXd::Zero(2 * N), f);
    const double Ep = planeStrain ? mat.E / (1 - mat.nu * mat.nu) : mat.E;
    const double nup = planeStrain ? mat.nu / (1 - mat.nu) : mat.nu;
    for (int n = 0; n < N; ++n) {
      EXPECT_NEAR(u[2 * n], p * mesh.nodes(0, n) / Ep, 1e-10 * p * mesh.length() / Ep);
      EXPECT_NEAR(u[2 * n + 1], -nup * p * mesh.nodes(1, n) / Ep, 1e-10 * p * mesh.length() / Ep);
    }
  }
}

// Mesh refinement converges: the entry-face centre displacement of the thesis
// block (all sides held but the entry face) under a uniform pressure on the entry
// face, p(y) = p0 sin^2(pi y / W) (smooth, no corner singularity). Bilinear
// elements converge at O(h^2) in displacement; successive differences must shrink
// by well over 2x per halving (observed order > 1.3).
TEST(Realtime2dFe, MeshRefinementConverges) {
  std::vector<double> w;
  for (int r : {2, 4, 8}) {
    TissueConfig cfg;
    cfg.mesh.nodes_depth = 4 * r + 1;
    cfg.mesh.nodes_lateral = 6 * r + 1;
    cfg.backend = Backend::Direct;
    Tissue t(cfg, {0.0, 0.06}, {1.0, 0.0}, 1e-3);
    const auto& m = t.mesh();
    Eigen::VectorXd f = Eigen::VectorXd::Zero(2 * m.nodeCount());
    for (int j = 0; j < m.ny; ++j) {
      const double lo = j > 0 ? m.ys[static_cast<std::size_t>(j)] - m.ys[static_cast<std::size_t>(j - 1)] : 0.0;
      const double hi = j + 1 < m.ny ? m.ys[static_cast<std::size_t>(j + 1)] - m.ys[static_cast<std::size_t>(j)] : 0.0;
      const double sn = std::sin(3.141592653589793 * m.ys[static_cast<std::size_t>(j)] / m.width());
      f[2 * m.node(0, j)] = 100.0 * sn * sn * 1e-3 * 0.5 * (lo + hi);  // smooth, zero at the held corners
    }
    const Eigen::VectorXd u = t.staticSolve(f);
    w.push_back(u[2 * m.node(0, m.ny / 2)]);
  }
  const double e1 = std::abs(w[1] - w[0]), e2 = std::abs(w[2] - w[1]);
  EXPECT_GT(e1, 0.0);
  EXPECT_LT(e2, 0.4 * e1) << w[0] << " " << w[1] << " " << w[2];
}

namespace {
TissueConfig smallTissue(Backend b, double alpha, double beta) {
  TissueConfig cfg;
  cfg.mesh.nodes_depth = 6;
  cfg.mesh.nodes_lateral = 7;
  cfg.mesh.grading = 2.0;
  cfg.backend = b;
  cfg.rayleigh_alpha = alpha;
  cfg.rayleigh_beta = beta;
  return cfg;
}
}  // namespace

// Undamped average-acceleration Newmark (gamma = 1/2, beta = 1/4) conserves
// 0.5 v'Mv + 0.5 u'Ku exactly for a linear system (to round-off), in both back-ends.
TEST(Realtime2dNewmark, UndampedConservesEnergy) {
  for (Backend b : {Backend::Direct, Backend::Modal}) {
    Tissue t(smallTissue(b, 0.0, 0.0), {0.0, 0.06}, {1.0, 0.0}, 2e-4);
    const int N = t.mesh().nodeCount();
    Eigen::VectorXd f = Eigen::VectorXd::Zero(2 * N);
    f[2 * t.path()[1].node] = 0.5;
    f[2 * t.path()[1].node + 1] = -0.2;
    const Eigen::VectorXd u0 = t.staticSolve(f);
    Eigen::VectorXd v0 = Eigen::VectorXd::Zero(2 * N);
    v0[2 * t.path()[2].node + 1] = 0.05;
    t.setState(u0, v0);
    const double E0 = t.kineticEnergy() + t.strainEnergy();
    const Eigen::VectorXd zero = Eigen::VectorXd::Zero(t.pathDofs());
    double maxDev = 0.0, minKin = 1e300, maxKin = 0.0;
    for (int n = 0; n < 2000; ++n) {
      t.predict();
      t.commit(zero);
      const double Ek = t.kineticEnergy();
      maxDev = std::max(maxDev, std::abs(Ek + t.strainEnergy() - E0));
      minKin = std::min(minKin, Ek);
      maxKin = std::max(maxKin, Ek);
    }
    EXPECT_LT(maxDev, 1e-9 * E0);
    EXPECT_GT(maxKin - minKin, 0.1 * E0);  // energy really moves between the two forms
  }
}

// Numerical damping: gamma > 1/2 must dissipate (so the test above would catch it).
TEST(Realtime2dNewmark, GammaAboveHalfDissipates) {
  auto cfg = smallTissue(Backend::Direct, 0.0, 0.0);
  cfg.newmark.gamma = 0.7;
  cfg.newmark.beta = 0.36;
  Tissue t(cfg, {0.0, 0.06}, {1.0, 0.0}, 2e-4);
  Eigen::VectorXd v0 = Eigen::VectorXd::Zero(2 * t.mesh().nodeCount());
  v0[2 * t.path()[2].node + 1] = 0.05;
  t.setState(Eigen::VectorXd::Zero(v0.size()), v0);
  const double E0 = t.kineticEnergy();
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(t.pathDofs());
  for (int n = 0; n < 2000; ++n) { t.predict(); t.commit(zero); }
  EXPECT_LT(t.kineticEnergy() + t.strainEnergy(), 0.9 * E0);
}

// The modal back-end is the same Newmark algorithm (Rayleigh damping is diagonal
// in the M-orthonormal eigenbasis): with damping and path loads both back-ends
// give the same path response to round-off, and the same compliance S.
TEST(Realtime2dNewmark, ModalEqualsDirect) {
  Tissue a(smallTissue(Backend::Direct, 0.01, 0.1), {0.0, 0.06}, {1.0, 0.0}, 1e-3);
  Tissue b(smallTissue(Backend::Modal, 0.01, 0.1), {0.0, 0.06}, {1.0, 0.0}, 1e-3);
  ASSERT_EQ(a.pathDofs(), b.pathDofs());
  EXPECT_LT((a.pathCompliance() - b.pathCompliance()).norm(), 1e-9 * a.pathCompliance().norm());
  Eigen::VectorXd f = Eigen::VectorXd::Zero(a.pathDofs());
  for (int n = 0; n < 300; ++n) {
    f[0] = 0.1 * std::sin(0.05 * n);
    f[3] = 0.05 * std::cos(0.03 * n);
    a.predict(); b.predict();
    a.commit(f); b.commit(f);
  }
  EXPECT_LT((a.pathU() - b.pathU()).norm(), 1e-8 * a.pathU().norm());
  EXPECT_LT((a.displacement() - b.displacement()).norm(), 1e-8 * a.displacement().norm());
}
