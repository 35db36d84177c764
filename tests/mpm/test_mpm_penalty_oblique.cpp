// Penalty contact of two deformable bodies in an OBLIQUE impact of two
// identical elastic spheres (the head-on impact is
// tests/mpm/test_mpm_penalty_spheres.cpp; the pair penalty,
// src/needlesim/engines/mpm/penalty_contact.*). Sphere 0 moves
// along +x, sphere 1 along -x, their paths b = R apart in y, so at first
// contact the line of centres makes 30 deg (sin = b / 2R) with the relative
// velocity. Checked against what rigid-body impact mechanics requires:
// momentum, energy, angular momentum about the common centre of mass, the
// impulse split into normal and tangential parts, and the spins.
// docs/validation/mpm.md, "Oblique sphere impacts".
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
using test::BodyMotion;
using test::bodyMotion;
using test::linearMaterial;

constexpr double kE = 1e5, kNu = 0.3, kRho = 1000;  // as the head-on test: c_p = 11.6 m/s
constexpr double kGap = 1e-3;                        // initial gap between the surfaces along the paths, m

struct ObliqueRun {
  double v0 = 0.5;  // speed of each sphere, m/s (relative speed 1 m/s as the collision)
  double b = 5e-3;  // impact parameter (distance of the paths), m
  double mu = 0.0;  // Coulomb coefficient between the spheres
  double R = 5e-3;  // sphere radius, m
  double kappa = -1;  // penaltyFactor (< 0: the default, 0.2)
  Shape shape = Shape::BSpline2;
  double dp1 = 0.0;  // point spacing of sphere 1, m (0: h / 2 as sphere 0)
};

struct ObliqueImpact {
  double m = 0;              // mass of one sphere, kg
  double drift = 0;          // max |E - E0| / E0, E = kinetic + strain + penalty
  double final = 0;          // final E / E0
  double balance = 0;        // max |E + W_f - E0| / E0, W_f the friction work done so far
  double momentum = 0;       // largest |P - P0| over the run / (m v0), P the total momentum (P0 = 0 for equal lattices)
  double angular = 0;        // largest |L - L0| / L0 over the run, L about the common centre of mass
  double angularFinal = 0;   // (L - L0) / L0 at the end (z component)
  double L0 = 0;             // initial angular momentum about the common centre of mass (z), kg m^2/s
  double thetaContact = 0;   // angle of the line of centres to x at first contact, rad
  double thetaApse = 0;      // same at the closest approach of the centres, rad
  double restitution = 0;    // -(u.n) / (u0.n), u relative velocity of the centres, n the apse line
  double tangential = 0;     // (u.t) / (u0.t), t perpendicular to n in the plane of motion
  double Jn = 0, Jt = 0;     // impulse on sphere 1 along n and against t (kg m/s)
  double dvPerpContact = 0;  // change of each sphere's velocity perpendicular to the first-contact line / v0
  double spin0 = 0, spin1 = 0;  // omega_z R / v0 of each sphere at the end
  double spinOff = 0;        // largest |omega_x|, |omega_y| R / v0 of the two at the end
  double lever0 = 0, lever1 = 0;  // L_spin,z / Jt of each sphere / R (moment arm of the tangential impulse)
  double contactTime = 0, hertz = 0;  // s
  int episodes = 0;
  double penetration = 0;    // largest overlap of two points' volumes, m
  double frictionWork = 0;   // J
  double rigid = 0;          // kinetic energy of the two spheres' rigid motions (translation + spin) at the end / E0
  std::size_t points = 0;
  long long steps = 0;
};

// The impulse and spins after an oblique impact from the spheres' motions before (a0, a1) and
// after (q0, q1), the line of centres at first contact and at the apse, and the energy E0.
void impulseAndSpins(ObliqueImpact& c, const BodyMotion& a0, const BodyMotion& a1, const BodyMotion& q0,
                     const BodyMotion& q1, const Vec3& nContact, const Vec3& nApse, double R, double v0, double e0) {
  // Relative velocity of the centres before (u0 = -2 v0 x) and after, split
  // along the apse line n and t = z x n (the direction in which sphere 1
  // slides past sphere 0 at the contact, u0.t = 2 v0 sin theta > 0).
  const Vec3 n = nApse, t = Vec3::UnitZ().cross(n);
  const Vec3 u0 = a1.velocity - a0.velocity, u1 = q1.velocity - q0.velocity;
  c.restitution = -u1.dot(n) / u0.dot(n);
  c.tangential = u1.dot(t) / u0.dot(t);
  const Vec3 J = q1.mass * (q1.velocity - a1.velocity);  // impulse on sphere 1 (sphere 0 gets -J to round-off)
  c.Jn = J.dot(n);
  c.Jt = -J.dot(t);
  const Vec3 tc = Vec3::UnitZ().cross(nContact);
  c.dvPerpContact = std::max(std::abs((q0.velocity - a0.velocity).dot(tc)), std::abs((q1.velocity - a1.velocity).dot(tc))) / v0;
  const Vec3 w0 = q0.spin(), w1 = q1.spin();
  c.spin0 = w0.z() * R / v0;
  c.spin1 = w1.z() * R / v0;
  c.spinOff = std::max({std::abs(w0.x()), std::abs(w0.y()), std::abs(w1.x()), std::abs(w1.y())}) * R / v0;
  c.rigid = (0.5 * q0.mass * q0.velocity.squaredNorm() + 0.5 * q1.mass * q1.velocity.squaredNorm() +
             0.5 * w0.dot(q0.spinMomentum) + 0.5 * w1.dot(q1.spinMomentum)) / e0;
  c.lever0 = q0.spinMomentum.z() / (c.Jt * R);
  c.lever1 = q1.spinMomentum.z() / (c.Jt * R);
}

// Two spheres of R = 5 mm filled on a 0.5 mm lattice (4,224 points each,
// as the head-on test) on a 1 mm grid, default penalty (kappa 0.2) and time
// step. The centres start at (-+X, -+b/2, 0) with 2X = sqrt(4R^2 - b^2) + gap:
// the spheres touch after gap / 2v0. The set-up is invariant under the
// rotation by 180 deg about z (it swaps the spheres), so the spins of the two
// spheres must be EQUAL (the same sense, along the orbital angular momentum
// +z): friction turns some orbital angular momentum into spin of both.
ObliqueImpact collideOblique(const ObliqueRun& u) {
  const double h = 1e-3, dp = h / 2, R = u.R, v0 = u.v0, b = u.b;
  const double X = 0.5 * (std::sqrt(4 * R * R - b * b) + kGap);
  MpmConfig cfg;
  cfg.h = h;
  // 4 cells of room beyond the spheres in x and y (each moves < 2.5 mm after
  // first contact at R = 5 mm; the run and the motion grow with R), 3 in z.
  const int room = 4 + static_cast<int>(std::ceil(std::max(0.0, R - 5e-3) / h));
  const int nx = static_cast<int>(std::ceil((X + R) / h)) + room;
  const int ny = static_cast<int>(std::ceil((0.5 * b + R) / h)) + room;
  const int nz = static_cast<int>(std::ceil(R / h)) + 3;
  cfg.origin = Vec3(-nx * h, -ny * h, -nz * h);
  cfg.cells = {2 * nx, 2 * ny, 2 * nz};
  cfg.bodies = 2;
  cfg.friction = u.mu;
  cfg.shape = u.shape;
  if (u.kappa > 0) cfg.penaltyFactor = u.kappa;
  cfg.threads = 1;
  MpmSolver s(cfg);
  s.addMaterial(linearMaterial(kE, kNu, kRho));
  ObliqueImpact c;
  c.points = addSphere(s, Vec3(-X, -0.5 * b, 0), R, dp, 0, Vec3(v0, 0, 0));
  const std::size_t n1 = addSphere(s, Vec3(X, 0.5 * b, 0), R, u.dp1 > 0 ? u.dp1 : dp, 1, Vec3(-v0, 0, 0));
  if (!(u.dp1 > 0)) EXPECT_EQ(n1, c.points);
  c.points += n1;
  s.finalize();

  const BodyMotion a0 = bodyMotion(s, 0), a1 = bodyMotion(s, 1);
  c.m = a0.mass;
  const Vec3 P0 = a0.mass * a0.velocity + a1.mass * a1.velocity;
  const double M = a0.mass + a1.mass;
  // Angular momentum about the common centre of mass, L = sum m x x v - M X_cm x V_cm.
  auto angularMomentum = [&](const BodyMotion& q0, const BodyMotion& q1) {
    Vec3 L = Vec3::Zero();
    for (std::size_t i = 0; i < s.size(); ++i) L += s.mass(i) * s.position(i).cross(s.velocity(i));
    const Vec3 xc = (q0.mass * q0.centre + q1.mass * q1.centre) / M;
    const Vec3 vc = (q0.mass * q0.velocity + q1.mass * q1.velocity) / M;
    return Vec3(L - M * xc.cross(vc));
  };
  const Vec3 L0 = angularMomentum(a0, a1);  // = m b v0 z
  c.L0 = L0.z();

  // Hertz's duration for the normal approach speed at first contact (the
  // normal and tangential problems uncouple for identical materials;
  // Johnson 1985, ch. 11 and 7): t_c = 2.868 (m*^2 / (R* E*^2 v_n))^(1/5).
  const double vn = 2 * v0 * std::sqrt(1 - b * b / (4 * R * R));
  const double mstar = a0.mass * a1.mass / (a0.mass + a1.mass), Rstar = 0.5 * R, Estar = kE / (2 * (1 - kNu * kNu));
  c.hertz = 2.868 * std::pow(mstar * mstar / (Rstar * Estar * Estar * vn), 0.2);

  double e = 0, e0 = 0, tOn = -1, tOff = -1, dmin = 1e300;
  bool touching = false;
  Vec3 nContact = Vec3::Zero(), nApse = Vec3::Zero();
  const double tEnd = kGap / (2 * v0) + 1.5 * c.hertz + 1e-3;
  while (s.time() < tEnd) {
    const double t0 = s.time();
    const StepReport r = s.step();
    e = r.kinetic + r.internal + r.contact;
    if (e0 == 0) e0 = e;
    c.drift = std::max(c.drift, std::abs(e - e0) / e0);
    c.penetration = std::max(c.penetration, r.penetration);
    c.frictionWork += r.frictionWork;
    c.balance = std::max(c.balance, std::abs(e + c.frictionWork - e0) / e0);
    const BodyMotion q0 = bodyMotion(s, 0), q1 = bodyMotion(s, 1);
    const Vec3 d = q1.centre - q0.centre;
    if (r.penetration > 0) {
      if (tOn < 0) {
        tOn = t0;
        nContact = d.normalized();
      }
      if (!touching) ++c.episodes;
      tOff = s.time();
      if (d.norm() < dmin) {
        dmin = d.norm();
        nApse = d.normalized();
      }
    }
    touching = r.penetration > 0;
    c.momentum = std::max(c.momentum, (q0.mass * q0.velocity + q1.mass * q1.velocity - P0).norm() / (c.m * v0));
    c.angular = std::max(c.angular, (angularMomentum(q0, q1) - L0).norm() / L0.norm());
  }
  c.final = e / e0;
  c.steps = s.steps();
  c.contactTime = tOn >= 0 ? tOff - tOn : 0.0;
  const BodyMotion q0 = bodyMotion(s, 0), q1 = bodyMotion(s, 1);
  c.angularFinal = (angularMomentum(q0, q1).z() - L0.z()) / L0.z();
  c.thetaContact = std::atan2(nContact.y(), nContact.x());
  c.thetaApse = std::atan2(nApse.y(), nApse.x());

  impulseAndSpins(c, a0, a1, q0, q1, nContact, nApse, R, v0, e0);
  return c;
}

void print(const ObliqueRun& u, const ObliqueImpact& c) {
  std::printf("oblique spheres (R %.0f mm, b %.2f R, v 2 x %.2f m/s, mu %.1f, %zu points): max drift %.2f %%, final "
              "E/E0 %.4f, max |E + W_f - E0| %.2f %%, max |P| %.1e m v0, max |L - L0| %.2f %% L0 (final %+.2f %%), line of centres %.1f deg at "
              "contact / %.1f deg at apse, restitution %.3f, tangential u_t'/u_t %.3f, Jt/Jn %.4f (Jn %.3f m v0), "
              "dv perp. to contact line %.3f v0, spin wR/v0 %+.4f / %+.4f (off-axis %.1e), Lspin/(Jt R) %.3f / %.3f, "
              "rigid-body kinetic energy at the end %.3f E0, contact %.3f ms (%d interval(s)) vs Hertz %.3f ms (ratio %.3f), overlap %.3f h, friction work %.3f E0, "
              "%lld steps\n",
              1e3 * u.R, u.b / u.R, u.v0, u.mu, c.points, 100 * c.drift, c.final, 100 * c.balance, c.momentum, 100 * c.angular,
              100 * c.angularFinal, c.thetaContact * 180 / M_PI, c.thetaApse * 180 / M_PI, c.restitution,
              c.tangential, c.Jt / c.Jn, c.Jn / (c.m * u.v0), c.dvPerpContact, c.spin0, c.spin1, c.spinOff, c.lever0,
              c.lever1, c.rigid, 1e3 * c.contactTime, c.episodes, 1e3 * c.hertz, c.contactTime / c.hertz, c.penetration / 1e-3,
              c.frictionWork / (0.5 * 2 * c.m * u.v0 * u.v0), c.steps);
}

}  // namespace

// Conservation laws and the normal part of the impact without friction
// (measured numbers of the pair penalty in parentheses; docs/validation/mpm.md
// "Oblique sphere impacts").
TEST(MpmPenaltyOblique, FrictionlessSpheres) {
  ObliqueRun u;
  const ObliqueImpact c = collideOblique(u);
  print(u, c);
  // 1. Momentum: every pair force is evaluated once and applied with
  //    opposite signs to the two points (antisymmetric to the bit) and the
  //    grid forces sum to the point forces (partition of unity), so the total
  //    momentum, exactly 0 at the start (the two lattices are images of each
  //    other under the 180 deg rotation about z, with opposite velocities), is
  //    conserved to round-off: 1e-12 m v0 (~1e4 double epsilons) leaves room
  //    for the sums over 8,448 points and ~2,000 steps (measured 3.2e-14;
  //    pair penalty 2.9e-14).
  EXPECT_LT(c.momentum, 1e-12);
  // 2. Issue 8 target for collisions (measured 0.26 %; pair penalty 0.29 %).
  EXPECT_LT(c.drift, 0.02);
  // 3. Angular momentum about the common centre of mass (L0 = m b v0 z):
  //    conserved by the contact forces (central pair forces), but not exactly
  //    by MPM's grid transfers; measured largest 0.33 % of L0 (the pair
  //    penalty: 3.6 %, with its spurious spins). 5 % bounds it.
  EXPECT_LT(c.angular, 0.05);
  // 4. Normal part: the spheres rebound along the line of centres as in the
  //    head-on test (e 0.86-0.92 there; measured 0.893 (0.925) at the normal
  //    approach speed 2 v0 cos 30 = 0.87 m/s) in one contact interval of about
  //    Hertz's duration for that normal speed (measured 0.979 (1.013); 20 % as
  //    the head-on test).
  EXPECT_GT(c.restitution, 0.8);
  EXPECT_LT(c.restitution, 1.0);
  EXPECT_EQ(c.episodes, 1);
  EXPECT_NEAR(c.contactTime / c.hertz, 1.0, 0.2);
  // 5. Symmetry (rotation by 180 deg about z): equal spins, none off the z
  //    axis (measured 1e-16 (1e-9) v0 / R off-axis, i.e. round-off in I^-1 L).
  EXPECT_NEAR(c.spin0, c.spin1, 1e-6);
  EXPECT_LT(c.spinOff, 1e-6);
  EXPECT_LT(c.frictionWork, 1e-12 * c.m * u.v0 * u.v0);  // mu = 0: none
}

// Coulomb friction mu = 0.3 between the spheres. Rigid spheres: the
// tangential impulse is at most mu Jn (sliding throughout) and the sticking
// value J_s = m_t u_t, m_t = m / 7 the effective mass of the contact points'
// tangential motion of two solid spheres (1/m_t = 2 (1/m + R^2 / (2/5 m R^2))),
// if the contact points stop sliding; with tangential compliance (elastic
// spheres; Maw, Barber & Fawcett 1976) the slip can reverse, up to J_t = 2 J_s
// where the tangential kinetic energy 1/2 m_t u_t^2 would be returned whole.
// Each sphere's spin comes from the moment of the tangential impulse, I omega
// = l Jt. For rigid spheres l = R; here the forces act on the outermost
// points, d_p/2 inside the surface, which the impact pushes in by up to
// delta/2 (delta = 1.35 mm, Hertz's largest approach of the centres at
// v_n = 0.87 m/s), so l lies in [R - d_p/2 - delta/2, R] = [0.81 R, R].
TEST(MpmPenaltyOblique, FrictionalSpheres) {
  ObliqueRun u;
  u.mu = 0.3;
  const ObliqueImpact c = collideOblique(u);
  print(u, c);
  // 1. Friction dissipates: E + W_f is conserved to the 2 % (measured
  //    density law 0.17 % / pair penalty 0.21 %, while E itself falls by the
  //    friction work, 7.4 / 5.4 % of E0) and E never rises above E0 by more than that.
  EXPECT_LT(c.balance, 0.02);
  EXPECT_LT(c.final, 1.0 + 0.02);
  EXPECT_GT(c.frictionWork, 0.0);
  // 2. Momentum to round-off (pair friction forces are opposite on the two
  //    points of a pair). Angular momentum: MPM's transfers do not conserve
  //    the angular momentum of a spinning body; the loss is proportional to
  //    the spins: 11-12 % of the spins' angular momentum in every run
  //    measured (pair penalty: 3.6 % of L0 with spins holding 32 % of L0;
  //    density law: 6.0 % of L0 with 48 %; friction on all pairs within H:
  //    6.4 % with 42 %; on the close pairs unscaled: 1.6 % with 13 %), while
  //    the frictionless run (no spin) keeps it to 0.33 %. So the bound is 5 %
  //    of L0 or 15 % of the spins' angular momentum, the larger.
  EXPECT_LT(c.momentum, 1e-12);
  const double spinShare = (c.lever0 + c.lever1) * c.Jt * u.R / c.L0;  // L_spin,0 + L_spin,1 over L0
  EXPECT_LT(c.angular, std::max(0.05, 0.15 * spinShare));
  // 3. Tangential impulse in [0, mu Jn] (measured Jt / Jn = 0.20; the pair
  //    penalty gave 0.131, and 0.142 with mu = 0: its lattice roughness), in
  //    the sense that opposes the sliding of the contact points.
  EXPECT_GT(c.Jt, 0.0);
  EXPECT_LT(c.Jt, (u.mu + 0.01) * c.Jn);
  // 4. Spins: both along +z (the sense of the orbit, see collideOblique),
  //    equal by symmetry, of the size the tangential impulse's moment gives:
  //    l / R = L_spin / (Jt R) in [0.81, 1] (measured 0.773 for both; pair
  //    penalty 0.806), widened by the angular momentum tolerance (5 % of L0 =
  //    m R v0, half of it on each sphere, is 0.08 of Jt R at the measured Jt =
  //    0.31 m v0; 0.12 kept from the pair penalty's Jt = 0.21 m v0).
  EXPECT_GT(c.spin0, 0.0);
  EXPECT_NEAR(c.spin0, c.spin1, 1e-6);
  EXPECT_LT(c.spinOff, 1e-6);
  EXPECT_GT(c.lever0, 0.81 - 0.12);
  EXPECT_LT(c.lever0, 1.0 + 0.12);
  EXPECT_GT(c.restitution, 0.8);
  EXPECT_EQ(c.episodes, 1);
}
