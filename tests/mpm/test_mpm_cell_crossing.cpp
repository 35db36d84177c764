// Cell-crossing noise of the shape functions (seed 000 section 5.2): the
// paper names the noise of its linear shape functions, as particles cross
// cell boundaries, as its main error, and the issue asks for a B-spline to
// remove it (docs/validation/mpm.md "Force noise, linear vs B-spline").
// In the needle set-ups contact switching at the needle dominates the force
// noise; this test isolates the cell crossing: a neo-Hookean block (8 mm
// long, 4 x 4 mm section, 1 mm grid, 2 x 2 x 2 points per cell) compressed
// in uniaxial strain (base fixed, sides on rollers) by a frictionless rigid
// plate to 30 % strain, so the points near the plate cross 2-3 cells while
// the stress state stays uniform. The plate force is compared with the
// closed form F = -sigma_xx(lambda) A (A = 4 x 4 mm, unchanged by the
// rollers), sigma_xx from the materials library at F = diag(lambda, 1, 1).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "needlesim/engines/mpm/mpm_solver.hpp"
#include "needlesim/materials/hyperelastic.hpp"

using namespace needlesim;
using namespace needlesim::mpm;

namespace {

constexpr double kL = 8e-3, kW = 4e-3;

struct Compression {
  double noise;     // N, RMS of the force minus its centred 21-step moving average
  double mean;      // N, mean force over the same steps
  double length;    // m, effective length L_eff of the block: the closed form fitted to the smoothed force
  double residual;  // RMS relative misfit of that fit
  int steps;
};

materials::Hyperelastic law() {
  materials::Hyperelastic l;
  l.kind = materials::LawKind::NeoHookean;
  l.C10 = 5e3;    // mu = 10 kPa
  l.bulk = 30e3;  // K = 30 kPa
  return l;
}

// Quasi-static plate force of the uniaxial-strain state of a block of length
// Le at plate travel d (N, compressive > 0).
double closedForm(double d, double Le = kL) {
  Mat3 F = Mat3::Identity();
  F(0, 0) = 1 - d / Le;
  return -materials::cauchyStress(law(), F)(0, 0) * kW * kW;
}

// RMS relative misfit of the smoothed forces f at travels d against the closed form for length Le.
double misfit(const std::vector<double>& d, const std::vector<double>& f, double Le) {
  double s = 0;
  for (std::size_t i = 0; i < d.size(); ++i) {
    const double e = closedForm(d[i], Le);
    s += (f[i] - e) * (f[i] - e) / (e * e);
  }
  return std::sqrt(s / static_cast<double>(d.size()));
}

Compression compress(Shape shape, double h) {
  MpmConfig cfg;
  cfg.h = h;
  cfg.shape = shape;
  cfg.origin = Vec3(-4 * h, -4 * h, -4 * h);
  cfg.cells = {static_cast<int>(kL / h) + 8, static_cast<int>(kW / h) + 8, static_cast<int>(kW / h) + 8};
  cfg.boxLo = Vec3(0, 0, 0);
  cfg.boxHi = Vec3(kL, kW, kW);
  cfg.faces = {FaceBC::Fixed, FaceBC::Free, FaceBC::Roller, FaceBC::Roller, FaceBC::Roller, FaceBC::Roller};
  cfg.threads = 1;
  cfg.massScaling = 10;  // P-wave speed sqrt((K + 4/3 mu) / (10 rho)) = 2.1 m/s
  MpmSolver s(cfg);
  MpmMaterial mat;
  mat.law = law();
  mat.density = 1000;
  s.addMaterial(mat);
  s.addBlock(Vec3(0, 0, 0), Vec3(kL, kW, kW), h / 2, 0, 0);
  RigidBody p;
  p.kind = RigidBody::Kind::Plane;
  p.point = Vec3(kL, 0, 0);
  p.normal = Vec3(-1, 0, 0);
  const int r = s.addRigid(p);
  s.finalize();
  // Plate speed ramped up over 20 ms (five transit times 4 L / c of the
  // block), then 10 mm/s: no impact wave. The slowest wave the loading
  // excites then carries a dynamic stress of about rho c v = 210 Pa at most
  // (10 x 1000 kg/m^3 x 2.1 m/s x 0.01 m/s), 2 % of the closed-form stress
  // at 2 mm (10.9 kPa).
  const double V = 0.01, ramp = 0.02;
  std::vector<double> F, D;
  double t = 0;
  while (kL - s.rigid(r).point.x() < 2.4e-3) {
    const double v = V * std::min(1.0, t / ramp);
    s.rigid(r).velocity = Vec3(-v, 0, 0);
    s.step();
    t += s.lastReport().dt;
    s.rigid(r).point.x() -= v * s.lastReport().dt;
    F.push_back(s.rigidForce(r).total.x());  // force on the plate (+x, pushed back by the block)
    D.push_back(kL - s.rigid(r).point.x());
  }
  Compression c{0, 0, 0, 0, static_cast<int>(F.size())};
  constexpr std::size_t w = 10;
  double sq = 0;
  std::vector<double> ds, fs;  // travel and smoothed force past the ramp
  for (std::size_t i = w; i + w < F.size(); ++i) {
    if (D[i] < 1e-3) continue;
    double avg = 0;
    for (std::size_t j = i - w; j <= i + w; ++j) avg += F[j];
    avg /= 2 * w + 1;
    sq += (F[i] - avg) * (F[i] - avg);
    c.mean += F[i];
    ds.push_back(D[i]);
    fs.push_back(avg);
  }
  const double n = static_cast<double>(ds.size());
  c.noise = std::sqrt(sq / n);
  c.mean /= n;
  // L_eff by golden-section search on [L - 2h, L + h] (the misfit is unimodal in Le).
  double a = kL - 2 * h, b = kL + h;
  const double g = (std::sqrt(5.0) - 1) / 2;
  while (b - a > 1e-7) {
    const double x1 = b - g * (b - a), x2 = a + g * (b - a);
    if (misfit(ds, fs, x1) < misfit(ds, fs, x2)) b = x2; else a = x1;
  }
  c.length = (a + b) / 2;
  c.residual = misfit(ds, fs, c.length);
  return c;
}

}  // namespace

// Measured (h = 1 mm): force noise linear 16.6 % of the mean force, B-spline
// 0.16 % (0.011 of the linear noise). The B-spline force follows the closed
// form of a block shorter by L - L_eff = 0.51 h (fit residual 1.6 %), and at
// h / 2 by 0.47 h (residual 0.5 %): first-order convergence to the exact
// force. The grid contact of the plate (eqs 14-21) acts on every node in the
// support of a touching point, so the plate's velocity reaches about half a
// cell into the block (docs/validation/mpm.md "Cell crossing"). The linear
// force fits L_eff = L + 0.26 h with a 5.4 % residual (its noise; not
// asserted). Tolerances: noise ratio 0.1 and level 1 % of the mean (margins
// 9 x and 6 x); L - L_eff within 0.3-0.7 h at both spacings, so a contact
// depth that does not shrink with h, or a stiffness error of 2.5 % or more at
// h = 1 mm, fails; fit residual 4 %, twice the dynamic stress of the loading
// (2 %, above).
TEST(MpmShape, BSplineRemovesCellCrossingNoise) {
  const Compression lin = compress(Shape::Linear, 1e-3), bsp = compress(Shape::BSpline2, 1e-3);
  const Compression fine = compress(Shape::BSpline2, 0.5e-3);
  const struct { const char* name; double h; const Compression& c; } rows[] = {
      {"linear", 1e-3, lin}, {"B-spline", 1e-3, bsp}, {"B-spline", 0.5e-3, fine}};
  for (const auto& r : rows)
    std::printf("%s, h %.2f mm: %d steps, mean force %.4g N, noise %.3g N (%.2f %% of the mean), "
                "L - L_eff = %.3f h (fit residual %.2f %%)\n",
                r.name, 1e3 * r.h, r.c.steps, r.c.mean, r.c.noise, 100 * r.c.noise / r.c.mean,
                (kL - r.c.length) / r.h, 100 * r.c.residual);
  EXPECT_LT(bsp.noise, 0.1 * lin.noise);
  EXPECT_LT(bsp.noise, 0.01 * bsp.mean);
  EXPECT_LT(fine.noise, 0.01 * fine.mean);
  for (const auto& [c, h] : {std::pair{bsp, 1e-3}, std::pair{fine, 0.5e-3}}) {
    EXPECT_GT((kL - c.length) / h, 0.3);
    EXPECT_LT((kL - c.length) / h, 0.7);
    EXPECT_LT(c.residual, 0.04);
  }
}
