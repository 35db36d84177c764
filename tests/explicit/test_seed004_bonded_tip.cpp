// Seed 004 section IV-B, Fig 13a: "we model the tissue and needle tip as one body but assign
// different material properties", a 2 mm needle tip pushed 0.5 mm, E_tissue = 25 kPa, nu = 0.45,
// bevel 10-80 deg. needlesim's engines cut a seam with a contact wedge (docs/validation/cohesive.md,
// Fig 13 table), which the paper does not; this check solves the paper's own reading directly: a
// rigid tip (steel against 25 kPa) bonded into a plane-strain linear elastic block, moved 0.5 mm
// along its axis, P, Q the tissue's resultant on the bevel edge and q_x, q_y on the bottom edge
// (seed 004 Fig 8). Geometry of the lost Fig 12 (assumed): the tip triangle with its heel on the
// entry face, the far face fixed, the other faces free; a uniform grid of bilinear quads, the tip
// the nodes inside the triangle (a staircase of h along the bevel, as the paper's element sets).
// docs/validation/cohesive.md "Fig 13a with the tip bonded into the tissue".
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <array>
#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>
#include <cmath>
#include <cstdio>
#include <vector>

#include "needlesim/engines/realtime2d/fe.hpp"

namespace {

struct TipForces {
  double P, Q, qx, qy;  // N per mm of thickness, on the needle
};

// The realtime2d engine's plane-strain bilinear quad (seed 003 eqs 3.6, 3.9): a square of side h,
// thickness t.
Eigen::Matrix<double, 8, 8> quadStiffness(double E, double nu, double h, double t) {
  needlesim::realtime2d::ElasticMaterial m;
  m.E = E;
  m.nu = nu;
  m.plane_strain = true;
  Eigen::Matrix<double, 2, 4> xy;
  xy << 0, h, h, 0, 0, 0, h, h;  // counter-clockwise from the lower left corner
  return needlesim::realtime2d::quadStiffness(xy, needlesim::realtime2d::elasticity(m), t);
}

// Block x in [0, W], y in [-H, H]; needle of diameter d on y in [-d/2, d/2], bottom edge y = -d/2,
// sharp point at (d / tan(alpha), -d/2), heel on x = 0. Tissue thickness 1 mm (forces per mm).
TipForces bondedTip(double alphaDeg, double h, double W = 24e-3, double H = 12e-3) {
  const double d = 2e-3, E = 25e3, nu = 0.45, push = 0.5e-3, t = 1e-3;
  const double L = d / std::tan(alphaDeg * M_PI / 180), yb = -d / 2;
  const int nx = static_cast<int>(std::lround(W / h)), ny = static_cast<int>(std::lround(2 * H / h));
  const int nn = (nx + 1) * (ny + 1);
  auto node = [&](int i, int j) { return j * (nx + 1) + i; };
  auto X = [&](int i) { return i * h; };
  auto Y = [&](int j) { return -H + j * h; };
  const double eps = 1e-9 * h;
  auto inTip = [&](double x, double y) {
    return x >= -eps && y >= yb - eps && y <= d / 2 - (d / L) * x + eps && x <= L + eps;
  };
  std::vector<char> rigid(nn, 0), fixedNode(nn, 0);
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i) {
      rigid[node(i, j)] = inTip(X(i), Y(j));
      fixedNode[node(i, j)] = i == nx;
    }
  // tissue elements: not all four nodes rigid
  const Eigen::Matrix<double, 8, 8> Ke = quadStiffness(E, nu, h, t);
  std::vector<std::array<int, 4>> tissue;
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const std::array<int, 4> c = {node(i, j), node(i + 1, j), node(i + 1, j + 1), node(i, j + 1)};
      if (!(rigid[c[0]] && rigid[c[1]] && rigid[c[2]] && rigid[c[3]])) tissue.push_back(c);
    }
  // free dofs
  std::vector<int> eq(2 * nn, -1);
  int nf = 0;
  for (int n = 0; n < nn; ++n)
    if (!rigid[n] && !fixedNode[n]) eq[2 * n] = nf++, eq[2 * n + 1] = nf++;
  Eigen::VectorXd up = Eigen::VectorXd::Zero(2 * nn);
  for (int n = 0; n < nn; ++n)
    if (rigid[n]) up[2 * n] = push;
  std::vector<Eigen::Triplet<double>> trip;
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(nf);
  for (const auto& c : tissue)
    for (int a = 0; a < 8; ++a) {
      const int ga = eq[2 * c[a / 2] + a % 2];
      if (ga < 0) continue;
      for (int b = 0; b < 8; ++b) {
        const int gdof = 2 * c[b / 2] + b % 2, gb = eq[gdof];
        if (gb >= 0)
          trip.emplace_back(ga, gb, Ke(a, b));
        else
          rhs[ga] -= Ke(a, b) * up[gdof];
      }
    }
  Eigen::SparseMatrix<double> K(nf, nf);
  K.setFromTriplets(trip.begin(), trip.end());
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(K);
  EXPECT_EQ(solver.info(), Eigen::Success);
  const Eigen::VectorXd uf = solver.solve(rhs);
  Eigen::VectorXd u = up;
  for (int n = 0; n < nn; ++n)
    if (eq[2 * n] >= 0) u[2 * n] = uf[eq[2 * n]], u[2 * n + 1] = uf[eq[2 * n + 1]];
  // force of the tissue elements on the rigid nodes = -(K_e u_e) at those nodes
  Eigen::VectorXd f = Eigen::VectorXd::Zero(2 * nn);
  for (const auto& c : tissue) {
    Eigen::Matrix<double, 8, 1> ue;
    for (int a = 0; a < 8; ++a) ue[a] = u[2 * c[a / 2] + a % 2];
    const Eigen::Matrix<double, 8, 1> fe = Ke * ue;
    for (int a = 0; a < 8; ++a) f[2 * c[a / 2] + a % 2] -= fe[a];
  }
  // bevel line through (0, d/2) and (L, yb): unit normal
  const double len = std::hypot(L, d), nxv = d / len, nyv = L / len;
  TipForces r{0, 0, 0, 0};
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i) {
      const int n = node(i, j);
      if (!rigid[n] || (f[2 * n] == 0 && f[2 * n + 1] == 0)) continue;
      const double dBottom = std::abs(Y(j) - yb), dBevel = std::abs((X(i) - 0) * nxv + (Y(j) - d / 2) * nyv);
      const double wBevel = dBevel < dBottom - eps ? 1.0 : (dBottom < dBevel - eps ? 0.0 : 0.5);
      r.P += wBevel * f[2 * n];
      r.Q += wBevel * f[2 * n + 1];
      r.qx += (1 - wBevel) * f[2 * n];
      r.qy += (1 - wBevel) * f[2 * n + 1];
    }
  return r;
}

// Seed 004 section IV-B and V: "smaller bevel angles resulted in larger axial and transverse tip
// forces"; "q_x decreases in a nonlinear manner with increase in bevel angle, while P decreases to a
// minimum value at approximately 35 deg and then begins to rise"; "Q monotonically decreases". The
// paper prints no number (Fig 13 is lost), so the trends are what is checked.
void checkFig13aTrends(double h) {
  const double angles[] = {10, 20, 35, 45, 60, 80};
  std::vector<TipForces> r;
  for (double a : angles) {
    r.push_back(bondedTip(a, h));
    const TipForces& f = r.back();
    std::printf("h %.2f mm, bevel %2.0f deg: P %8.3f Q %8.3f q_x %8.3f q_y %8.3f  F_x %8.3f F_y %8.3f mN per mm\n",
                h * 1e3, a, f.P * 1e3, f.Q * 1e3, f.qx * 1e3, f.qy * 1e3, (f.P + f.qx) * 1e3, (f.Q + f.qy) * 1e3);
  }
  for (std::size_t k = 1; k < r.size(); ++k) {
    EXPECT_LT(std::abs(r[k].P + r[k].qx), std::abs(r[k - 1].P + r[k - 1].qx)) << "F_x at " << angles[k];
    EXPECT_LT(std::abs(r[k].Q + r[k].qy), std::abs(r[k - 1].Q + r[k - 1].qy)) << "F_y at " << angles[k];
    EXPECT_LT(std::abs(r[k].qx), std::abs(r[k - 1].qx)) << "q_x at " << angles[k];
    // Q's split from q_y follows the staircase: it moves by up to 11 % between h = 0.2 and 0.1 mm
    // (35 deg), so Q may stay flat within that between neighbouring angles (35 -> 45 deg)
    EXPECT_LT(std::abs(r[k].Q), 1.11 * std::abs(r[k - 1].Q)) << "Q at " << angles[k];
  }
  EXPECT_LT(std::abs(r[5].Q), 0.5 * std::abs(r[3].Q));
  EXPECT_LT(std::abs(r[3].Q), std::abs(r[0].Q));
  // P: lowest at 35 deg among 10, 20, 35 and below its 80 deg value (45 and 60 deg lie within the
  // staircase's few per cent of each other)
  EXPECT_LT(std::abs(r[2].P), std::abs(r[1].P));
  EXPECT_LT(std::abs(r[1].P), std::abs(r[0].P));
  EXPECT_LT(std::abs(r[2].P), std::abs(r[5].P));
}

}  // namespace

TEST(Seed004BondedTip, SmallerBevelGivesLargerTipForces) { checkFig13aTrends(0.2e-3); }

TEST(Seed004BondedTip, LongTrendsHoldOnTheFinerGrid) { checkFig13aTrends(0.1e-3); }
