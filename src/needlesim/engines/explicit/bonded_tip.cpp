// Seed 004 Fig 13a with the tip bonded into the tissue (bonded_tip.hpp): a linear static solve on a
// uniform grid of plane-strain bilinear quads (seed 003 eqs 3.6, 3.9, the realtime2d element), the tip's
// nodes moved rigidly, the tissue's nodal forces on them summed by the edge each lies nearest.
#include "needlesim/engines/explicit/bonded_tip.hpp"

#include <fmt/format.h>

#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>
#include <array>
#include <cmath>
#include <vector>

#include "needlesim/core/error.hpp"
#include "needlesim/engines/realtime2d/fe.hpp"
#include "needlesim/engines/run_cost.hpp"
#include "needlesim/insertion/motion_profile.hpp"
#include "needlesim/io/table.hpp"
#include "needlesim/materials/material_spec.hpp"
#include "needlesim/scenario/scenario.hpp"

namespace needlesim::explicit_fe {

namespace {

// Block x in [0, W], y in [-H, H]; the needle on |y| <= d/2, bottom edge y = -d/2, sharp point at
// (d / tan(alpha), -d/2), heel on x = 0: the bevel edge runs from (0, d/2) to (L, -d/2).
struct TipGrid {
  int nx = 0, ny = 0;
  double h = 0.0, H = 0.0, d = 0.0, L = 0.0;
  std::vector<char> rigid, fixed;
  int node(int i, int j) const { return j * (nx + 1) + i; }
  double x(int i) const { return i * h; }
  double y(int j) const { return -H + j * h; }
  int nodes() const { return (nx + 1) * (ny + 1); }
};

TipGrid tipGrid(const BondedTipInput& in) {
  TipGrid g;
  g.h = in.elementSize;
  g.H = 0.5 * in.width;
  g.d = in.diameter;
  g.L = in.diameter / std::tan(in.bevelAngle);
  g.nx = static_cast<int>(std::lround(in.length / g.h));
  g.ny = static_cast<int>(std::lround(in.width / g.h));
  g.rigid.assign(static_cast<std::size_t>(g.nodes()), 0);
  g.fixed.assign(g.rigid.size(), 0);
  const double eps = 1e-9 * g.h, yb = -0.5 * g.d;
  for (int j = 0; j <= g.ny; ++j)
    for (int i = 0; i <= g.nx; ++i) {
      const double X = g.x(i), Y = g.y(j);
      const bool inTip = X >= -eps && Y >= yb - eps && Y <= 0.5 * g.d - (g.d / g.L) * X + eps && X <= g.L + eps;
      g.rigid[static_cast<std::size_t>(g.node(i, j))] = inTip;
      g.fixed[static_cast<std::size_t>(g.node(i, j))] = i == g.nx;
    }
  return g;
}

// The tissue's elements: every grid square but those with all four corners in the tip.
std::vector<std::array<int, 4>> tissueElements(const TipGrid& g) {
  std::vector<std::array<int, 4>> out;
  for (int j = 0; j < g.ny; ++j)
    for (int i = 0; i < g.nx; ++i) {
      const std::array<int, 4> c = {g.node(i, j), g.node(i + 1, j), g.node(i + 1, j + 1), g.node(i, j + 1)};
      bool all = true;
      for (int n : c) all = all && g.rigid[static_cast<std::size_t>(n)];
      if (!all) out.push_back(c);
    }
  return out;
}

// The displacement of every dof: the tip's nodes moved by `push` along x, the far face held, the
// rest from K_ff u_f = -K_fp u_p.
Eigen::VectorXd solveDisplacements(const TipGrid& g, const std::vector<std::array<int, 4>>& tissue,
                                   const Eigen::Matrix<double, 8, 8>& Ke, double push) {
  const int nn = g.nodes();
  std::vector<int> eq(2 * static_cast<std::size_t>(nn), -1);
  int nf = 0;
  Eigen::VectorXd u = Eigen::VectorXd::Zero(2 * nn);
  for (int n = 0; n < nn; ++n) {
    const auto k = static_cast<std::size_t>(n);
    if (g.rigid[k]) u[2 * n] = push;
    if (!g.rigid[k] && !g.fixed[k]) eq[2 * k] = nf++, eq[2 * k + 1] = nf++;
  }
  std::vector<Eigen::Triplet<double>> trip;
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(nf);
  for (const auto& c : tissue)
    for (int a = 0; a < 8; ++a) {
      const int ga = eq[static_cast<std::size_t>(2 * c[a / 2] + a % 2)];
      if (ga < 0) continue;
      for (int b = 0; b < 8; ++b) {
        const int dof = 2 * c[b / 2] + b % 2, gb = eq[static_cast<std::size_t>(dof)];
        if (gb >= 0)
          trip.emplace_back(ga, gb, Ke(a, b));
        else
          rhs[ga] -= Ke(a, b) * u[dof];
      }
    }
  Eigen::SparseMatrix<double> K(nf, nf);
  K.setFromTriplets(trip.begin(), trip.end());
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(K);
  if (solver.info() != Eigen::Success) throw SolverError("explicit: the bonded tip's stiffness matrix is singular");
  const Eigen::VectorXd uf = solver.solve(rhs);
  for (int n = 0; n < nn; ++n)
    if (const int e = eq[2 * static_cast<std::size_t>(n)]; e >= 0) u[2 * n] = uf[e], u[2 * n + 1] = uf[e + 1];
  return u;
}

// The tissue's force on each tip node, given to the edge it lies nearest (half each on a tie).
BondedTipForces splitTipForces(const TipGrid& g, const std::vector<std::array<int, 4>>& tissue,
                               const Eigen::Matrix<double, 8, 8>& Ke, const Eigen::VectorXd& u) {
  Eigen::VectorXd f = Eigen::VectorXd::Zero(u.size());
  for (const auto& c : tissue) {
    Eigen::Matrix<double, 8, 1> ue;
    for (int a = 0; a < 8; ++a) ue[a] = u[2 * c[a / 2] + a % 2];
    const Eigen::Matrix<double, 8, 1> fe = Ke * ue;
    for (int a = 0; a < 8; ++a) f[2 * c[a / 2] + a % 2] -= fe[a];
  }
  const double len = std::hypot(g.L, g.d), nx = g.d / len, ny = g.L / len, yb = -0.5 * g.d, eps = 1e-9 * g.h;
  BondedTipForces r;
  for (int j = 0; j <= g.ny; ++j)
    for (int i = 0; i <= g.nx; ++i) {
      const int n = g.node(i, j);
      if (!g.rigid[static_cast<std::size_t>(n)]) continue;
      const double dBottom = std::abs(g.y(j) - yb), dBevel = std::abs(g.x(i) * nx + (g.y(j) - 0.5 * g.d) * ny);
      const double wBevel = dBevel < dBottom - eps ? 1.0 : (dBottom < dBevel - eps ? 0.0 : 0.5);
      r.P += wBevel * f[2 * n];
      r.Q += wBevel * f[2 * n + 1];
      r.qx += (1 - wBevel) * f[2 * n];
      r.qy += (1 - wBevel) * f[2 * n + 1];
    }
  return r;
}

}  // namespace

BondedTipForces solveBondedTip(const BondedTipInput& in) {
  const TipGrid g = tipGrid(in);
  realtime2d::ElasticMaterial m;
  m.E = in.youngs;
  m.nu = in.poisson;
  m.plane_strain = true;
  Eigen::Matrix<double, 2, 4> xy;
  xy << 0, g.h, g.h, 0, 0, 0, g.h, g.h;  // counter-clockwise from the lower left corner
  const Eigen::Matrix<double, 8, 8> Ke = realtime2d::quadStiffness(xy, realtime2d::elasticity(m), in.thickness);
  const auto tissue = tissueElements(g);
  return splitTipForces(g, tissue, Ke, solveDisplacements(g, tissue, Ke, in.push));
}

namespace {

BondedTipInput inputFrom(const Scenario& sc) {
  BondedTipInput in;
  const MotionProfile motion(sc.insertion);
  const auto moduli = materials::smallStrainModuli(sc.tissue.layers.front().material);
  in.diameter = sc.needle.outer_diameter;
  in.bevelAngle = sc.needle.bevel_angle;
  in.youngs = moduli.youngs();
  in.poisson = moduli.poisson();
  in.push = motion.at(motion.duration()).depth - sc.insertion.start_depth;
  in.length = sc.tissue.length;
  in.width = sc.tissue.width;
  in.elementSize = sc.model.explicit_fe.element_size;
  in.thickness = sc.needle.outer_diameter;  // a slab as thick as the needle, as every 2D explicit result
  return in;
}

}  // namespace

void runBondedTip(const Scenario& sc, ResultSink& sink) {
  const BondedTipInput in = inputFrom(sc);
  const BondedTipForces f = solveBondedTip(in);
  io::Table t({{"push", "m"}, {"P", "N"}, {"Q", "N"}, {"q_x", "N"}, {"q_y", "N"}});
  t.addRow({in.push, f.P, f.Q, f.qx, f.qy});
  sink.table("bonded_tip", std::move(t));
  sink.result("tip_force_axial", f.P, "N", "P: the tissue's axial force on the bonded tip's bevel edge (seed 004 Fig 8)");
  sink.result("tip_force_lateral", f.Q, "N",
              "Q: the tissue's lateral force on the bevel edge, + towards the bevel side (seed 004 Fig 8)");
  sink.result("wall_force_axial", f.qx, "N", "q_x: the tissue's axial force on the tip's bottom edge");
  sink.result("wall_force_lateral", f.qy, "N", "q_y: the tissue's lateral force on the bottom edge, + towards the bevel side");
  sink.result("final_force", -(f.P + f.qx), "N", "axial force on the needle: -(P + q_x), > 0 pushing the tip in");
  sink.note(fmt::format(
      "Bonded tip (seed 004 Fig 13a, docs/validation/cohesive.md): a rigid {:g} deg bevel tip bonded into a linear "
      "elastic plane-strain block (E {:.4g} kPa, nu {:g}, the first layer's small-strain moduli) and moved {:g} mm; "
      "{} x {} quads of {:g} mm; forces times a slab as thick as the needle ({:g} mm).",
      in.bevelAngle * 180.0 / M_PI, in.youngs * 1e-3, in.poisson, in.push * 1e3,
      std::lround(in.length / in.elementSize), std::lround(in.width / in.elementSize), in.elementSize * 1e3,
      in.thickness * 1e3));
}

StepPlan bondedTipStepPlan(const Scenario& sc) {
  StepPlan p;
  p.engine = "explicit";
  p.steps = 1.0;  // one static solve
  p.spacing = sc.model.explicit_fe.element_size;
  p.spacingName = "the grid spacing (model.explicit.element_size)";
  p.fewerSteps = "nothing: one static solve";
  // The cost of every 2D explicit run (run_cost.hpp): the set-up per element (here the assembly
  // and the sparse factorisation) and one step of every element.
  p.updatesPerStep = static_cast<double>(tissueElements(tipGrid(inputFrom(sc))).size());
  p.updates = "elements";
  p.secondsPerUpdate = run_cost::kExplicitPlaneElement;
  p.setupSeconds = run_cost::kExplicitSetupPerElement * p.updatesPerStep;
  return p;
}

}  // namespace needlesim::explicit_fe
