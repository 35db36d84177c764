// Density contact of two deformable bodies (MpmConfig::bodyContact = Density,
// the default; src/needlesim/engines/mpm/density_contact.*): the law's
// threshold (touching faces feel no force, any overlap does, no spurious gap),
// its calibration to the pair penalty's face pressure kappa M delta / d_p,
// forces that are minus the gradient of the energy the code reports, and the
// pair search against a brute-force sum. The impacts are in
// test_mpm_penalty_{contact,spheres,oblique}.cpp; docs/validation/mpm.md,
// "Density contact".
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include <Eigen/Geometry>

#include "needlesim/engines/mpm/density_contact.hpp"
#include "needlesim/engines/mpm/mpm_solver.hpp"
#include "needlesim/engines/mpm/penalty_contact.hpp"
#include "mpm_test_materials.hpp"

using namespace needlesim;
using namespace needlesim::mpm;

namespace {

using test::linearMaterial;

constexpr double kE = 1e5, kNu = 0.3;
// P-wave modulus K + 4/3 mu of the St Venant-Kirchhoff law (the stiffness scale kappa M d_p).
const double kM = kE / (3 * (1 - 2 * kNu)) + 4.0 / 3.0 * kE / (2 * (1 + kNu));

MpmConfig twoBodies(BodyContact law = BodyContact::Density) {
  MpmConfig cfg;
  cfg.h = 1e-3;
  cfg.origin = Vec3(-4e-3, -4e-3, -4e-3);
  cfg.cells = {18, 16, 16};
  cfg.bodies = 2;
  cfg.threads = 1;
  cfg.bodyContact = law;
  return cfg;
}

struct FaceForces {
  double largest = 0;  // largest |f| on any point, N
  double column = 0;   // x force on body 1 per central column (2H from the face's edges) / d_p^2, Pa
  double net = 0;      // |sum of all forces|, N
  double energy = 0;   // J
};

// Two 4 x 8 x 8 mm blocks of 0.5 mm points (16 x 16 points on the faces), the
// second one's face at x = 4 mm + gap, shifted by `lateral` along y and z.
FaceForces faces(double gap, double lateral) {
  const double dp = 0.5e-3;
  MpmSolver s(twoBodies());
  s.addMaterial(linearMaterial(kE, kNu, 1000));
  s.addBlock(Vec3(0, 0, 0), Vec3(4e-3, 8e-3, 8e-3), dp, 0, 0);
  s.addBlock(Vec3(4e-3 + gap, lateral, lateral), Vec3(8e-3 + gap, 8e-3 + lateral, 8e-3 + lateral), dp, 0, 1);
  std::vector<Vec3> f;
  FaceForces r;
  r.energy = s.contactForces(f);
  Vec3 sum = Vec3::Zero();
  int columns = 0;
  for (std::size_t p = 0; p < s.size(); ++p) {
    r.largest = std::max(r.largest, f[p].norm());
    sum += f[p];
    if (s.body(p) != 1) continue;
    const Vec3 x = s.position(p) - Vec3(0, lateral, lateral);
    const bool central = x.y() > 3e-3 && x.y() < 5e-3 && x.z() > 3e-3 && x.z() < 5e-3;  // >= 2H = 3 mm from the edges
    if (!central) continue;
    r.column += f[p].x();
    if (x.x() < 4e-3 + gap + dp) ++columns;  // one point of the outer layer per column
  }
  r.column /= columns * dp * dp;
  r.net = sum.norm();
  return r;
}

}  // namespace

// The threshold phi* is the volume fraction two touching faces of equal
// aligned lattices give (outer layers d_p apart): there the force is zero
// (up to the round-off of the two sums of phi), with a gap it is exactly
// zero (no attraction, no force across a gap), and an overlap delta = 0.01
// d_p pushes the faces apart with the pair penalty's face pressure kappa M
// delta / d_p (the calibration of c_q; first order in delta, the profile of
// phi curves by ~1 % over 0.01 d_p). A lattice shifted by half a spacing
// along the face touches at phi within 0.05 % of phi* (the lattice ripple of
// the kernel of support 3 d_p): its force at touching is that of an overlap
// below 0.001 d_p. Forces are central and antisymmetric: the net force is
// round-off.
TEST(MpmDensityContact, TouchingFacesFeelNoForceAndNoGap) {
  const double dp = 0.5e-3, kappa = MpmConfig{}.penaltyFactor;
  const double F0 = kappa * kM * dp * dp;  // force of one pair of the pair penalty at overlap d_p
  const FaceForces touch = faces(0.0, 0.0), gap = faces(0.01 * dp, 0.0), in = faces(-0.01 * dp, 0.0);
  const FaceForces shifted = faces(0.0, 0.5 * dp), shiftedIn = faces(-0.001 * dp, 0.5 * dp);
  const double p = kappa * kM * 0.01;  // kappa M delta / d_p at delta = 0.01 d_p
  std::printf("flat faces: touching largest |f| %.2e F0, gap %.2e F0; overlap 0.01 d_p: pressure %.5g Pa (kappa M "
              "delta / d_p = %.5g, ratio %.4f), net force %.1e of the largest; half-spacing shift: touching largest "
              "|f| %.2e F0, overlap 0.001 d_p %.2e F0\n",
              touch.largest / F0, gap.largest / F0, in.column, p, in.column / p, in.net / in.largest, shifted.largest / F0,
              shiftedIn.largest / F0);
  EXPECT_LT(touch.largest, 1e-12 * F0);
  EXPECT_EQ(gap.largest, 0.0);
  EXPECT_EQ(gap.energy, 0.0);
  EXPECT_GT(in.column, 0.0);  // body 1 pushed along +x, away from body 0
  EXPECT_NEAR(in.column / p, 1.0, 0.02);
  EXPECT_LT(in.net, 1e-12 * in.largest);
  EXPECT_LT(shifted.largest, shiftedIn.largest);
}

// The forces are minus the gradient of the energy the code reports (central
// differences of contactForces' energy when one point moves by +-1e-8 m,
// 2e-5 of a spacing: truncation ~1e-8 of the forces (measured 1.3e-6 at
// +-1e-7 m, the barrier's (G/r)^6 is steep), round-off ~1e-11), for
// two blocks on different, offset lattices (0.5 and 0.4 mm) overlapping by
// 0.15 mm (0.33 of the contact distance: into the barrier beyond 0.3 d), for
// both laws; the forces sum to zero and so do their moments (central pair
// forces: momentum and angular momentum are conserved to round-off).
TEST(MpmDensityContact, ForcesAreMinusTheEnergyGradient) {
  for (BodyContact law : {BodyContact::Density, BodyContact::Penalty}) {
    MpmSolver s(twoBodies(law));
    s.addMaterial(linearMaterial(kE, kNu, 1000));
    s.addBlock(Vec3(0, 0, 0), Vec3(3e-3, 3e-3, 3e-3), 0.5e-3, 0, 0);
    s.addBlock(Vec3(2.85e-3, 0.13e-3, -0.21e-3), Vec3(5.65e-3, 3.33e-3, 2.99e-3), 0.4e-3, 0, 1);
    std::vector<Vec3> f, g;
    const double e = s.contactForces(f);
    ASSERT_GT(e, 0.0);
    Vec3 sum = Vec3::Zero(), moment = Vec3::Zero();
    double fmax = 0, xf = 0;
    std::vector<std::size_t> order(s.size());
    for (std::size_t p = 0; p < s.size(); ++p) {
      sum += f[p];
      moment += s.position(p).cross(f[p]);
      fmax = std::max(fmax, f[p].norm());
      xf += s.position(p).norm() * f[p].norm();
      order[p] = p;
    }
    // The 12 points with the largest forces and 4 with small ones.
    std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return f[a].norm() > f[b].norm(); });
    std::vector<std::size_t> probe(order.begin(), order.begin() + 12);
    for (std::size_t p : order)
      if (f[p].norm() > 0 && f[p].norm() < 0.05 * fmax && probe.size() < 16) probe.push_back(p);
    const double eps = 1e-8;
    double worst = 0;
    for (std::size_t p : probe)
      for (int d = 0; d < 3; ++d) {
        const Vec3 x = s.position(p);
        Vec3 dx = Vec3::Zero();
        dx[d] = eps;
        s.setPosition(p, x + dx);
        const double ep = s.contactForces(g);
        s.setPosition(p, x - dx);
        const double em = s.contactForces(g);
        s.setPosition(p, x);
        worst = std::max(worst, std::abs((ep - em) / (2 * eps) + f[p][d]));
      }
    std::printf("%s: energy %.6e J, largest |f| %.4e N, worst |dE/dx + f| %.2e of it over %zu points, net force %.1e, "
                "net moment %.1e (of sum |x||f|)\n",
                law == BodyContact::Density ? "density law" : "pair penalty", e, fmax, worst / fmax, probe.size(),
                sum.norm() / fmax, moment.norm() / xf);
    EXPECT_LT(worst, 1e-6 * fmax);
    EXPECT_LT(sum.norm(), 1e-12 * fmax);
    EXPECT_LT(moment.norm(), 1e-12 * xf);
  }
}

// The pair search (candidates of p2g within the kernel's reach of 2 cells,
// one-sided sweep from body 0's cells, reactions) against a brute-force O(n^2)
// sum of phi over all points of two overlapping blocks on different, offset
// lattices: the energy each step reports (at its end positions) equals
// sum_q c_q U((phi(x_q) - phi*) / s) of the brute-force phi there, to
// round-off (a pair that enters the support during a step of 1e-7 s would add
// W ~ 1e-20 of phi*). Three steps: the later ones take the candidates' cells
// from the previous final pass.
TEST(MpmDensityContact, SearchMatchesBruteForce) {
  MpmConfig cfg = twoBodies();
  cfg.friction = 0.3;
  cfg.fixedTimeStep = 1e-7;
  MpmSolver s(cfg);
  s.addMaterial(linearMaterial(kE, kNu, 1000));
  s.addBlock(Vec3(0, 0, 0), Vec3(3e-3, 3e-3, 3e-3), 0.5e-3, 0, 0);
  s.addBlock(Vec3(2.8e-3, 0.13e-3, -0.21e-3), Vec3(5.6e-3, 3.33e-3, 2.99e-3), 0.4e-3, 0, 1);
  s.finalize();
  const std::size_t n = s.size();
  std::vector<double> radius(n);
  std::vector<std::uint8_t> body(n);
  for (std::size_t p = 0; p < n; ++p) {
    radius[p] = 0.5 * std::cbrt(s.volume0(p));
    body[p] = static_cast<std::uint8_t>(s.body(p));
  }
  const DensityLaw D = makeDensityLaw(radius, body, s.particleSpacing(), cfg.h);
  EXPECT_EQ(D.reach, 2);  // H = 3 x 0.5 mm = 1.5 h
  const PairPenalty law(cfg.penaltyFactor * kM * s.particleSpacing(), radius, 1.0, 1);
  auto bruteForce = [&]() {
    double e = 0;
    int touching = 0;
    for (std::size_t q = 0; q < n; ++q) {
      double phi = 0;
      for (std::size_t p = 0; p < n; ++p)
        if (body[p] != body[q]) phi += s.volume0(p) * D.kernel.value((s.position(q) - s.position(p)).norm());
      const int B = 1 - body[q];
      const double delta = (phi - D.phiStar[B]) / D.slope[B], d = radius[q] + 0.5 * D.spacing[B];
      if (delta <= 0) continue;
      e += 2 * radius[q] * radius[q] / (s.particleSpacing() * s.particleSpacing()) * law.pairEnergy(delta, d);
      ++touching;
    }
    EXPECT_GT(touching, 20);
    return e;
  };
  for (int step = 0; step < 3; ++step) {
    const StepReport r = s.step();
    const double e = bruteForce();
    std::printf("step %d: energy %.9e J, brute force %.9e J\n", step + 1, r.contact, e);
    EXPECT_NEAR(r.contact, e, 1e-12 * e) << "step " << step + 1;
  }
}
