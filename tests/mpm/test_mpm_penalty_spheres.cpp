// Penalty contact of two deformable bodies on CURVED surfaces: two identical
// elastic spheres colliding head-on (the classic MPM test of Sulsky, Chen &
// Schreyer 1994, here in 3D with the pair penalty,
// src/needlesim/engines/mpm/penalty_contact.*). The flat-face
// collision of two blocks is tests/mpm/test_mpm_penalty_contact.cpp; this one
// checks energy, momentum, restitution and the contact duration against
// Hertz's closed form. docs/validation/mpm.md, "Two spheres (curved surfaces)".
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "needlesim/engines/mpm/mpm_solver.hpp"
#include "mpm_test_materials.hpp"
#include "mpm_test_spheres.hpp"

using namespace needlesim;
using namespace needlesim::mpm;

namespace {

using test::addSphere;
using test::linearMaterial;
using test::Sums;
using test::sums;

constexpr double kE = 1e5, kNu = 0.3, kRho = 1000;  // St Venant-Kirchhoff, c_p = 11.6 m/s, M = 134.6 kPa
constexpr double kGap = 1e-3;                        // initial gap between the surfaces, m

struct SphereImpact {
  double drift = 0;         // max |E - E0| / E0, E = kinetic + strain + penalty
  double final = 0;         // final E / E0
  double restitution = 0;   // separation / approach speed of the centres of mass along x
  double cmVelocity = 0;    // largest |centre-of-mass velocity of the pair| over the run, m/s (starts at 0)
  double contactTime = 0;   // start of the first to end of the last step with overlapping points, s
  int episodes = 0;         // separate contact intervals (1: no chatter)
  double hertz = 0;         // Hertz contact duration, s
  double penetration = 0;   // largest overlap of two points' volumes, m
  double frictionWork = 0;  // J over the run
  double e0 = 0;
  std::size_t points = 0;
  long long steps = 0;
};

struct SphereRun {
  Shape shape = Shape::BSpline2;
  double v0 = 0.5;     // approach speed of each sphere, m/s
  double kappa = -1;   // penaltyFactor (< 0: the default, 0.2)
  double mu = 0.0;     // Coulomb coefficient between the spheres
  double R = 5e-3;     // sphere radius, m
};

// Two spheres (points h/2 = 0.5 mm, 4,224 each for R = 5 mm) 1 mm apart
// along x approach at 2 x v0 on a 1 mm grid (6 cells beyond the outer poles,
// 3 beside the spheres: the rebound carries each ~1.5 mm out); default time step (k_t 0.4, pair step limit). The run lasts
// the approach, 1.5 Hertz durations and 1 ms of free flight, so the
// centre-of-mass velocities at the end are those after separation.
SphereImpact collideSpheres(const SphereRun& u) {
  const double h = 1e-3, dp = h / 2, R = u.R, v0 = u.v0;
  MpmConfig cfg;
  cfg.h = h;
  cfg.shape = u.shape;
  const int nx = static_cast<int>(std::ceil((2 * R + 0.5 * kGap) / h)) + 6;
  const int ny = static_cast<int>(std::ceil(R / h)) + 3;
  cfg.origin = Vec3(-nx * h, -ny * h, -ny * h);
  cfg.cells = {2 * nx, 2 * ny, 2 * ny};
  cfg.bodies = 2;
  cfg.friction = u.mu;
  if (u.kappa > 0) cfg.penaltyFactor = u.kappa;
  cfg.threads = 1;
  MpmSolver s(cfg);
  s.addMaterial(linearMaterial(kE, kNu, kRho));
  const double xc = R + 0.5 * kGap;
  SphereImpact c;
  c.points = addSphere(s, Vec3(-xc, 0, 0), R, dp, 0, Vec3(v0, 0, 0));
  const std::size_t n1 = addSphere(s, Vec3(xc, 0, 0), R, dp, 1, Vec3(-v0, 0, 0));
  EXPECT_EQ(n1, c.points);
  c.points += n1;
  s.finalize();

  // Hertz (e.g. Johnson, Contact Mechanics, 1985, ch. 11): two equal
  // spheres of mass m (the lattice's mass, 0.8 % above 4/3 pi R^3 rho) and
  // radius R, t_c = 2.868 (m*^2 / (R* E*^2 v_rel))^(1/5), m* = m/2, R* = R/2,
  // 1/E* = 2 (1 - nu^2) / E.
  const Sums s0 = sums(s);
  const double mstar = 0.5 * s0.m0, Rstar = 0.5 * R, Estar = kE / (2 * (1 - kNu * kNu)), vrel = 2 * v0;
  c.hertz = 2.868 * std::pow(mstar * mstar / (Rstar * Estar * Estar * vrel), 0.2);

  const double mtot = s0.m0 + s0.m1;
  double e = 0, tOn = -1, tOff = -1;
  bool touching = false;
  const double tEnd = kGap / vrel + 1.5 * c.hertz + 1e-3;
  while (s.time() < tEnd) {
    const double t0 = s.time();
    const StepReport r = s.step();
    e = r.kinetic + r.internal + r.contact;
    if (c.e0 == 0) c.e0 = e;
    c.drift = std::max(c.drift, std::abs(e - c.e0) / c.e0);
    c.penetration = std::max(c.penetration, r.penetration);
    c.frictionWork += r.frictionWork;
    if (r.penetration > 0) {
      if (tOn < 0) tOn = t0;
      if (!touching) ++c.episodes;
      tOff = s.time();
    }
    touching = r.penetration > 0;
    const Sums m = sums(s);
    c.cmVelocity = std::max(c.cmVelocity, ((m.p0 + m.p1) / mtot).norm());
  }
  c.final = e / c.e0;
  c.steps = s.steps();
  c.contactTime = tOn >= 0 ? tOff - tOn : 0.0;
  const Sums m = sums(s);
  c.restitution = (m.p1.x() / m.m1 - m.p0.x() / m.m0) / vrel;
  return c;
}


void print(const char* what, const SphereRun& u, const SphereImpact& c) {
  std::printf("%s %s (R %.0f mm, v 2 x %.2f m/s, kappa %.2f, mu %.1f, %zu points): max drift %.2f %%, final E/E0 "
              "%.4f, restitution %.3f, max |v_cm| %.2g v0, contact %.3f ms (%d interval(s)) vs Hertz %.3f ms "
              "(ratio %.3f), largest overlap %.3f h, friction work %.2g E0, %lld steps\n",
              what, test::shapeName(u.shape), 1e3 * u.R, u.v0, u.kappa > 0 ? u.kappa : MpmConfig{}.penaltyFactor, u.mu,
              c.points, 100 * c.drift, c.final, c.restitution, c.cmVelocity / u.v0, 1e3 * c.contactTime, c.episodes,
              1e3 * c.hertz, c.contactTime / c.hertz, c.penetration / 1e-3, c.frictionWork / c.e0, c.steps);
}

}  // namespace

// The impact of the issue's collision test (2 x 0.5 m/s, h = 1 mm, points
// h/2) between spheres of R = 5 mm, with Coulomb friction 0.3 as in the block
// test. Penalty stiffness: a pressure p on a point's face overlaps it by
// p d_p / (kappa M); Hertz's peak pressure here is p0 = 2 E* a / (pi R*) =
// 27 kPa = 0.2 M, so the default kappa = 0.2 (tuned on the block impact, where
// the face pressure rho c v is 0.04 M) with the linear pair law alone let the
// points sink by a whole d_p and pass through each other (measured: overlap
// 0.50 h, drift 13.5 %, restitution 0.59; docs/validation/mpm.md); the
// barrier now stops them (DefaultPenaltyStopsTheIssueImpact below). kappa = 1
// keeps the linear law's predicted overlap at 0.2 d_p (measured 0.17 h = 0.35
// d_p, just into the barrier beyond 0.3 d_p).
TEST(MpmPenaltySpheres, LongTwoElasticSpheresCollideLikeHertz) {
  for (Shape sh : {Shape::BSpline2, Shape::Linear}) {
    SphereRun u;
    u.shape = sh;
    u.kappa = 1.0;
    u.mu = 0.3;
    const SphereImpact c = collideSpheres(u);
    print("two spheres", u, c);
    // 1. Issue 8 target for collisions, with both shapes. Measured 0.67 %
    //    (B-spline) and 0.60 % (linear), below the blocks' 1.8 / 1.2 % (the
    //    curved contact loads gradually, the flat faces at once).
    EXPECT_LT(c.drift, 0.02);
    // 2. Momentum: each pair force is evaluated from both sides, exactly
    //    antisymmetric, and the grid forces sum to zero (partition of unity),
    //    so the total momentum is conserved to round-off. It starts at exactly
    //    0 (mirror lattices, +-v0); measured 2e-14 v0; 1e-12 v0 (~1e4 double
    //    epsilons) leaves room for the sums over 8,448 points and ~1,000 steps.
    EXPECT_LT(c.cmVelocity, 1e-12 * u.v0);
    // 3. Elastic rebound: Hertz's quasi-static impact has e = 1; the vibration
    //    left in the spheres (v_rel / c_p = 0.09) and the grid's dispersion of
    //    the impact take the rest (measured 0.872 / 0.928; 0.913 at h/2 with
    //    the linear law alone).
    EXPECT_GT(c.restitution, 0.8);
    EXPECT_EQ(c.episodes, 1);  // one contact interval, no chatter
    // 4. Hertz's contact duration (4.47 ms). Measured 0.849 (B-spline) / 0.835
    //    (linear) of it (0.866 / 0.846 with the linear law alone): the MPM spheres are stiffer at first touch, because the
    //    lattice sphere's pole is a flat face of 32 points (equivalent radius
    //    1.6 mm; a flat punch, linear in the approach) and the Hertz contact
    //    radius, a = 1.9 mm, spans only two cells. (The impact is also beyond
    //    Hertz's small strains: approach 1.5 mm = 0.61 R*.) The error is
    //    first order in h: at (linear law alone)
    //    h = 0.5 mm (points 0.25 mm) the ratio is 0.933 (Richardson: 1.000), at
    //    R = 8 mm on the same grid 0.882. 20 % holds the h = 1 mm error (13-15 %)
    //    with a margin for the shape and the penalty's compliance (kappa 0.5:
    //    0.893), and would catch a contact twice too stiff or soft in time
    //    (t_c ~ k^(-1/2): +-20 % is a factor 0.7-1.6 in stiffness).
    EXPECT_NEAR(c.contactTime / c.hertz, 1.0, 0.2);
    // Identical spheres head-on: no relative slip (similar materials, Dundurs'
    // beta = 0: the normal and tangential contact problems uncouple, Johnson 1985),
    // so friction does no work (measured ~1e-30 E0).
    EXPECT_LT(c.frictionWork, 1e-6 * c.e0);
  }
}

// The default penalty (kappa 0.2) on curved surfaces at a milder impact
// (2 x 0.25 m/s: Hertz p0 = 0.15 M, predicted overlap of the linear law
// 0.76 d_p): the points must not pass through each other (overlap < 0.8 d_p =
// 0.4 h, measured 0.19 h; 0.29 h with the linear law alone), the energy
// target holds (measured 0.93 %) and the spheres rebound (0.910).
// The contact lasts 0.78 of Hertz's 5.14 ms (0.83 with the linear law): the Hertz contact radius (1.5 mm)
// is now the size of the lattice's flat pole (a_f = 1.6 mm), which behaves as
// a flat punch (a linear spring 2 E* a_f: t_c = pi sqrt(m* / (2 E* a_f)) =
// 3.9 ms, the duration the MPM spheres approach at lower speeds, 4.1 ms at
// 2 x 0.05 m/s),
// so the duration is reported, not asserted.
TEST(MpmPenaltySpheres, DefaultPenaltyHoldsAMildImpact) {
  SphereRun u;
  u.v0 = 0.25;
  const SphereImpact c = collideSpheres(u);
  print("two spheres, default kappa", u, c);
  EXPECT_LT(c.drift, 0.02);
  EXPECT_LT(c.penetration, 0.4e-3);
  EXPECT_LT(c.cmVelocity, 1e-12 * u.v0);
  EXPECT_GT(c.restitution, 0.8);
  EXPECT_EQ(c.episodes, 1);
}

// The issue's impact (2 x 0.5 m/s, Hertz p0 = 0.2 M) with the default kappa
// 0.2 and friction 0.3: the linear pair law alone would need an overlap of
// p0 d_p / (kappa M) = d_p, i.e. the points would pass through each other
// (measured before the barrier: overlap 0.50 h = d_p, drift 17.9 %,
// restitution 0.26, two contact intervals). The barrier beyond 0.3 d must stop
// them, with the energy target and an elastic rebound: the barrier acts on
// each pair's distance, so the deepest pair stays within half a spacing,
// d_p / 2 = 0.25 h. Measured: overlap 0.226 h, drift 1.02 %, e 0.871,
// contact 0.901 of Hertz's 4.47 ms.
// docs/validation/mpm.md, section 5.
TEST(MpmPenaltySpheres, DefaultPenaltyStopsTheIssueImpact) {
  SphereRun u;
  u.mu = 0.3;
  const SphereImpact c = collideSpheres(u);
  print("two spheres, pair penalty", u, c);
  EXPECT_LT(c.drift, 0.02);
  EXPECT_LT(c.penetration, 0.25e-3);
  EXPECT_LT(c.cmVelocity, 1e-12 * u.v0);
  EXPECT_GT(c.restitution, 0.8);
  EXPECT_EQ(c.episodes, 1);
  EXPECT_NEAR(c.contactTime / c.hertz, 1.0, 0.2);
}
