// Penalty contact of two deformable bodies (
// src/needlesim/engines/mpm/penalty_contact.*): the collision of two elastic
// blocks must conserve kinetic + strain + penalty energy (issue target 2 %),
// bounce with a coefficient of restitution near 1, keep the overlap a small
// fraction of h, and let friction remove energy only while the faces slide.
// docs/validation/mpm.md, "Energy in the collision test".
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <utility>
#include <vector>

#include "needlesim/engines/mpm/mpm_solver.hpp"
#include "mpm_test_materials.hpp"

using namespace needlesim;
using namespace needlesim::mpm;

namespace {

using test::linearMaterial;

Vec3 bodyVelocity(const MpmSolver& s, int body) {
  Vec3 p = Vec3::Zero();
  double m = 0;
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (s.body(i) != body) continue;
    p += s.mass(i) * s.velocity(i);
    m += s.mass(i);
  }
  return p / m;
}

struct Impact {
  double drift = 0;         // max |E - E0| / E0 over the run, E = kinetic + strain + penalty
  double contactDrift = 0;  // the same up to the last step in contact
  double final = 0;         // final E / E0
  double restitution = 0;   // separation / approach speed along x (centre-of-mass velocities)
  double tangential = 0;    // final relative velocity along y of the centres of mass, m/s
  double penetration = 0;   // largest overlap of two points' volumes, m
  double frictionWork = 0;  // J over the run
  double e0 = 0;
  long long steps = 0;
};

struct Collision {
  Shape shape = Shape::BSpline2;
  double mu = 0.0;
  double nu = 0.3;
  double vt = 0.0;  // sliding velocity of each block along y (+ / -), m/s
  int refine = 1;   // divides h (1 mm) and the particle spacing (h / 2)
};

// Two elastic blocks (8 mm cubes, E 100 kPa, 1000 kg/m^3), the set-up of
// MpmVerification.TwoElasticBlocksCollideEnergyDrift: 3 mm apart, approach
// along x at 2 x 0.5 m/s (plus +-vt along y for an oblique impact), h = 1 mm,
// particles h/2, default time-step factor, 8 ms (contact from 3.0 to ~4.9 ms).
Impact collide(const Collision& u) {
  const double h = 1e-3 / u.refine, a = 8e-3, d = 3e-3;
  MpmConfig cfg;
  cfg.h = h;
  cfg.shape = u.shape;
  cfg.origin = Vec3(-4e-3, -6e-3, -4e-3);
  cfg.cells = {30 * u.refine, 20 * u.refine, 16 * u.refine};
  cfg.bodies = 2;
  cfg.friction = u.mu;
  cfg.threads = 1;
  MpmSolver s(cfg);
  s.addMaterial(linearMaterial(1e5, u.nu, 1000));
  const double v0 = 0.5;
  s.addBlock(Vec3(0, 0, 0), Vec3(a, a, a), h / 2, 0, 0, Vec3(v0, u.vt, 0));
  s.addBlock(Vec3(a + d, 0, 0), Vec3(2 * a + d, a, a), h / 2, 0, 1, Vec3(-v0, -u.vt, 0));
  s.finalize();
  Impact c;
  double e = 0;
  while (s.time() < 0.008) {
    const StepReport r = s.step();
    e = r.kinetic + r.internal + r.contact;
    if (c.e0 == 0) c.e0 = e;
    c.drift = std::max(c.drift, std::abs(e - c.e0) / c.e0);
    c.penetration = std::max(c.penetration, r.penetration);
    c.frictionWork += r.frictionWork;
    if (r.penetration > 0) c.contactDrift = c.drift;  // the largest drift up to the end of the contact
  }
  c.final = e / c.e0;
  c.steps = s.steps();
  const Vec3 u0 = bodyVelocity(s, 0), u1 = bodyVelocity(s, 1);
  c.restitution = (u1.x() - u0.x()) / (2 * v0);
  c.tangential = u0.y() - u1.y();
  return c;
}


}  // namespace

// Issue 8 target: total energy drift below 2 % in the two-block collision
// with friction, with B-splines and with linear shapes, at the grid of the
// velocity-contact test (which drifts 10.6 % / 8.9 %).
TEST(MpmPenaltyContact, TwoElasticBlocksCollideEnergyDrift) {
  for (Shape sh : {Shape::BSpline2, Shape::Linear}) {
    Collision u;
    u.shape = sh;
    u.mu = 0.3;
    const Impact c = collide(u);
    std::printf("penalty collision %s (h = 1 mm, mu 0.3): max drift %.2f %%, final E/E0 %.4f, restitution %.3f, "
                "largest overlap %.3f h, friction work %.2g E0, %lld steps\n",
                test::shapeName(sh), 100 * c.drift, c.final, c.restitution, c.penetration / 1e-3, c.frictionWork / c.e0,
                c.steps);
    // Measured 1.6 % (B-spline) and 1.4 % (linear). What is left is the
    // FLIP/grid error of the impact plus the half-step kinetic energy of an
    // explicit step; it grows with the stiffness (kappa 1: 5.5 %).
    EXPECT_LT(c.drift, 0.02);
    // The overlap stays well inside a particle spacing (0.5 h): measured 0.15 h.
    EXPECT_LT(c.penetration, 0.2e-3);
    // Head-on and mirror-symmetric: nothing slides, so friction does no work
    // (measured 1e-28 E0; with the normal taken at the node nearest the pair
    // instead of at its midpoint, 1.3 % of E0).
    EXPECT_LT(c.frictionWork, 1e-6 * c.e0);
  }
}

// Frictionless head-on impact of two blocks with nu = 0: every cross-section
// is in uniaxial strain, the 1D problem of two equal elastic bars, which
// exchange their velocities exactly (coefficient of restitution 1). The
// penalty conserves the energy through the impact; what keeps e below 1 is
// the grid's dispersion of the step wave (8 cells per bar): a stiffer
// penalty (sharper wave) gives a lower e (kappa 0.1 / 0.2 / 0.5 / 1: e 0.973 /
// 0.913 / 0.883 / 0.859).
TEST(MpmPenaltyContact, HeadOnBarsSeparateWithTheirApproachSpeed) {
  Collision u;
  u.nu = 0.0;
  const Impact p = collide(u);
  std::printf("nu 0 head-on: restitution penalty %.3f (drift through the contact %.2f %%, over the run %.2f %%, final "
              "E/E0 %.4f, overlap %.3f h)\n",
              p.restitution, 100 * p.contactDrift, 100 * p.drift, p.final, p.penetration / 1e-3);
  EXPECT_GT(p.restitution, 0.9);  // measured 0.913
  // Through the impact the energy stays within 2.5 % (measured 1.9 %); after
  // the separation the free vibration of the bars wobbles by +-1.5 % in MPM,
  // so the whole run drifts 3.4 %.
  EXPECT_LT(p.contactDrift, 0.025);
  EXPECT_LT(p.penetration, 0.2e-3);
}

// Oblique impact: the blocks also slide past each other at 2 x vt along y.
// Without friction the contact is conservative (final energy = E0 and the
// sliding speed unchanged); with mu the faces slide during the whole contact
// (mu times the normal impulse is below the sticking one), so Coulomb's law
// fixes the change of the relative sliding speed, mu times the change of the
// normal relative speed, and the energy lost equals the friction work.
TEST(MpmPenaltyContact, FrictionRemovesEnergyOnlyWhileSliding) {
  Collision u;
  u.vt = 0.5;
  const Impact f0 = collide(u);
  u.mu = 0.3;
  const Impact f = collide(u);
  const double dvn = 1.0 * (1.0 + f.restitution);  // change of the relative normal speed
  const double dvt = 1.0 - f.tangential;           // change of the relative sliding speed (initially 1 m/s)
  std::printf("oblique: mu 0 final E/E0 %.4f drift %.2f %% sliding %.3f m/s; mu 0.3 final %.4f, friction work %.4f "
              "E0, E + W %.4f, dv_t %.3f vs mu dv_n %.3f\n",
              f0.final, 100 * f0.drift, f0.tangential, f.final, f.frictionWork / f.e0, f.final + f.frictionWork / f.e0,
              dvt, 0.3 * dvn);
  EXPECT_LT(f0.drift, 0.02);
  EXPECT_NEAR(f0.tangential, 1.0, 0.05);
  EXPECT_LT(f0.frictionWork, 1e-6 * f0.e0);
  EXPECT_LT(f.final, f0.final - 0.05);
  EXPECT_NEAR(f.final + f.frictionWork / f.e0, f0.final, 0.02);
  EXPECT_NEAR(dvt / (0.3 * dvn), 1.0, 0.1);
}

// The penalty contact at half the grid spacing (h = 0.5 mm, points h/2; kappa,
// alpha and the contact distance d_p follow the grid): the drift must not
// grow with refinement, and the overlap stays the same fraction of h.
TEST(MpmPenaltyContact, LongCollisionDriftUnderRefinement) {
  Collision u;
  u.mu = 0.3;
  u.refine = 2;
  const Impact c = collide(u);
  std::printf("penalty collision B-spline h = 0.5 mm: max drift %.2f %%, final E/E0 %.4f, restitution %.3f, overlap "
              "%.3f h, %lld steps\n",
              100 * c.drift, c.final, c.restitution, c.penetration / 0.5e-3, c.steps);
  EXPECT_LT(c.drift, 0.02);
  EXPECT_LT(c.penetration, 0.2 * 0.5e-3);
}

// The pair search visits each pair once, from the cell of its body-0 point,
// and gives the partner the opposite force (penalty_contact.cpp). Against a
// brute-force O(n^2) search over all points of two overlapping blocks on
// different, offset lattices (different radii; pairs across cell faces in
// all directions): the same pairs (the stored energy of the pairs in contact
// at the step's start, evaluated at its end, and the largest overlap, to
// round-off), and the forces act on both bodies (momentum of the initially
// resting pair stays zero while each body gains some).
TEST(MpmPenaltyContact, PairSearchMatchesBruteForce) {
  MpmConfig cfg;
  cfg.h = 1e-3;
  cfg.origin = Vec3(-4e-3, -4e-3, -4e-3);
  cfg.cells = {14, 12, 12};
  cfg.bodies = 2;
  cfg.friction = 0.3;
  cfg.threads = 1;
  // A short step (pair omega dt ~ 0.06 at the deepest overlap): the first step
  // has no pair step limit yet, and the barrier's force at 0.65 d would throw
  // the pairs apart within a default step (nothing left to compare).
  cfg.fixedTimeStep = 1e-7;
  MpmSolver s(cfg);
  const double E = 1e5, nu = 0.3;
  s.addMaterial(linearMaterial(E, nu, 1000));
  s.addBlock(Vec3(0, 0, 0), Vec3(3e-3, 3e-3, 3e-3), 0.5e-3, 0, 0);
  // 0.4 mm lattice, shifted off the first one and overlapping it by ~0.3 mm along x.
  s.addBlock(Vec3(2.7e-3, 0.13e-3, -0.21e-3), Vec3(5.9e-3, 3.33e-3, 2.99e-3), 0.4e-3, 0, 1);
  s.finalize();
  const std::size_t n = s.size();
  std::vector<Vec3> x0(n);
  std::vector<double> rad(n);
  for (std::size_t p = 0; p < n; ++p) {
    x0[p] = s.position(p);
    rad[p] = 0.5 * std::cbrt(s.volume0(p));
  }
  std::vector<std::pair<std::size_t, std::size_t>> pairs;
  double deltaMax = 0;
  for (std::size_t p = 0; p < n; ++p)
    for (std::size_t q = 0; q < n; ++q) {
      if (s.body(p) != 0 || s.body(q) != 1) continue;
      const double delta = rad[p] + rad[q] - (x0[p] - x0[q]).norm();
      if (delta <= 0) continue;
      pairs.emplace_back(p, q);
      deltaMax = std::max(deltaMax, delta);
    }
  ASSERT_GT(pairs.size(), 100u);
  const StepReport r = s.step();
  // Pair stiffness kappa M d_p (penalty_contact.hpp), M = K + 4/3 mu of the St Venant-Kirchhoff law.
  const double M = E / (3 * (1 - 2 * nu)) + 4.0 / 3.0 * E / (2 * (1 + nu));
  const double k = cfg.penaltyFactor * M * s.particleSpacing();
  // Pair potential U(delta) = int_0^delta f, the law of penalty_contact.hpp
  // (f = k y up to y = 0.3 d, then k y (G / (d - y))^6, G = 0.7 d), here by
  // composite Simpson quadrature of the force (20,000 panels on the barrier
  // piece: error ~ 3024 / 180 (h / r)^4 < 1e-16 U), independent of the closed form.
  auto force = [k](double y, double d) {
    const double s = 0.3 * d;
    return y <= s ? k * y : k * y * std::pow((d - s) / (d - y), 6);
  };
  auto simpson = [&](double a, double b, double d) {
    const int n = 20000;
    const double hh = (b - a) / n;
    double sum = force(a, d) + force(b, d);
    for (int i = 1; i < n; ++i) sum += (i % 2 ? 4 : 2) * force(a + i * hh, d);
    return sum * hh / 3;
  };
  double energy = 0, deep = 0;
  for (const auto& [p, q] : pairs) {
    const double d = rad[p] + rad[q];
    deep = std::max(deep, (d - (x0[p] - x0[q]).norm()) / d);
    const double delta = d - (s.position(p) - s.position(q)).norm();
    if (delta <= 0) continue;
    const double s3 = 0.3 * d;
    energy += delta <= s3 ? 0.5 * k * delta * delta : 0.5 * k * s3 * s3 + simpson(s3, delta, d);
  }
  // The lattices overlap by up to 0.29 mm (0.65 d): deep into the barrier.
  EXPECT_GT(deep, 0.5);
  EXPECT_GT(energy, 0.0);
  std::printf("pair search: %zu pairs, energy %.6e J (brute force %.6e J), overlap %.4e m (%.4e m)\n", pairs.size(),
              r.contact, energy, r.penetration, deltaMax);
  EXPECT_NEAR(r.contact, energy, 1e-12 * energy);
  EXPECT_NEAR(r.penetration, deltaMax, 1e-15);
  Vec3 mom[2] = {Vec3::Zero(), Vec3::Zero()};
  for (std::size_t p = 0; p < n; ++p) mom[s.body(p)] += s.mass(p) * s.velocity(p);
  EXPECT_LT(mom[0].x(), 0.0);  // pushed apart along x
  EXPECT_GT(mom[1].x(), 0.0);
  EXPECT_LT((mom[0] + mom[1]).norm(), 1e-12 * mom[1].norm());
  // Later steps take the cells the bodies occupy from the previous step's
  // final pass (markNearBodies), not from a pass over the points: the search
  // must still find every pair in contact (the deepest overlap) at the start
  // of each step.
  for (int step = 0; step < 3; ++step) {
    double deepest = 0;
    for (std::size_t p = 0; p < n; ++p)
      for (std::size_t q = 0; q < n; ++q)
        if (s.body(p) == 0 && s.body(q) == 1)
          deepest = std::max(deepest, rad[p] + rad[q] - (s.position(p) - s.position(q)).norm());
    ASSERT_GT(deepest, 0.0);
    EXPECT_NEAR(s.step().penetration, deepest, 1e-15) << "step " << step + 2;
  }
}

// The barrier of the pair law (penalty_contact.hpp) on one pair: two single
// points (one body each, d_p = h/2, a uniform grid field: each moves as a
// particle) thrown at each other with the relative speed 2 omega d (omega^2 =
// k / m_r, here 14.7 m/s = 1.26 c_p), i.e. the kinetic energy 2 k d^2 of the
// pair, four times the linear law's 1/2 k d^2 at r = 0: the linear law alone
// lets them pass through each other. The barrier's potential reaches 2 k d^2
// at delta = 0.635 d (closed form, pairEnergy), so they must stop there, with
// r > 0 and finite forces and energy, and bounce back. The worst case of the
// explicit update: the pair's own oscillation is the whole motion, and the
// step, which follows the tangent stiffness (alpha / omega_t, ~ r^3.5 near
// the bottom) and the approach (alpha r / v_n), changes by 25x within it;
// the symplectic update with a varying step gains energy at first order in
// alpha, so the test runs the default alpha = 0.15 and alpha / 3.
struct PairBounce {
  double deepest = 0, rmin = 1, restitution = 0, drift = 0;
  long long steps = 0;
};
PairBounce bouncePair(double alpha) {
  MpmConfig cfg;
  cfg.h = 1e-3;
  cfg.origin = Vec3(-4e-3, -4e-3, -4e-3);
  cfg.cells = {8, 8, 8};
  cfg.bodies = 2;
  cfg.threads = 1;
  cfg.penaltyStepFactor = alpha;
  // The pair law: the density law sees no contact between two lone points
  // (one point's phi, V W(r) <= 0.12, stays below the touching value 0.25 of
  // a lattice half-space; docs/models/mpm.md).
  MpmSolver s(cfg);
  const double E = 1e5, nu = 0.3, rho = 1000, d = 0.5e-3;
  s.addMaterial(linearMaterial(E, nu, rho));
  const double M = E / (3 * (1 - 2 * nu)) + 4.0 / 3.0 * E / (2 * (1 + nu));
  const double k = cfg.penaltyFactor * M * d, mr = 0.5 * rho * d * d * d, omega = std::sqrt(k / mr);
  const double v = omega * d;  // each point: relative speed 2 omega d
  s.addParticle(Vec3(-0.6 * d - 0.05e-3, 0.1e-3, 0.2e-3), d * d * d, 0, 0, Vec3(v, 0, 0));
  s.addParticle(Vec3(0.6 * d - 0.05e-3, 0.1e-3, 0.2e-3), d * d * d, 0, 1, Vec3(-v, 0, 0));
  s.finalize();
  EXPECT_NEAR(s.particleSpacing(), d, 1e-12 * d);
  PairBounce b;
  double e0 = 0;
  bool touched = false;
  while (s.time() < 10 / omega) {  // contact ~ 1.5 / omega
    const StepReport r = s.step();
    const double e = r.kinetic + r.internal + r.contact;
    EXPECT_TRUE(std::isfinite(e) && std::isfinite(r.dt) && r.dt > 0);
    if (e0 == 0) e0 = e;
    b.drift = std::max(b.drift, std::abs(e - e0) / e0);
    b.rmin = std::min(b.rmin, (s.position(0) - s.position(1)).norm() / d);
    b.deepest = std::max(b.deepest, r.penetration / d);
    touched = touched || r.penetration > 0;
    if (touched && r.penetration == 0) break;  // separated (the grid is only 8 cells wide)
  }
  b.steps = s.steps();
  b.restitution = (s.velocity(1).x() - s.velocity(0).x()) / (2 * v);
  std::printf("barrier, alpha %.3f: deepest overlap %.3f d (closed form 0.635 d), closest r %.3f d, restitution "
              "%.4f, drift %.2f %%, %lld steps\n",
              alpha, b.deepest, b.rmin, b.restitution, 100 * b.drift, b.steps);
  return b;
}

TEST(MpmPenaltyContact, BarrierStopsAFastPairShortOfTheCentre) {
  const PairBounce a = bouncePair(0.15), b = bouncePair(0.05);
  for (const PairBounce& c : {a, b}) {
    EXPECT_GT(c.rmin, 0.3);         // the barrier holds (linear law: r -> 0 and through)
    EXPECT_GT(c.restitution, 0.9);  // bounced back (passing through would give e < 0)
  }
  // The turning point converges to the closed form and the energy error is
  // first order: a third of the step, about a third of the error.
  EXPECT_NEAR(b.deepest, 0.635, 0.01);
  EXPECT_NEAR(b.restitution, 1.0, 0.5 * std::abs(a.restitution - 1.0));
  EXPECT_LT(b.drift, 0.5 * a.drift);
}
