#pragma once
// Density contact of two deformable bodies in the MPM solver
// (MpmConfig::bodyContact = Density; docs/models/mpm.md
// "Density contact of two bodies"). The pair search, the reaction buffers,
// the scatter and the friction of the pair penalty (penalty_contact.*) are
// shared; what differs is the normal law, here a many-body potential.
//
// Kept from seed 000 eqs 14-21: one velocity field per body, interaction only
// where the bodies meet, Coulomb friction with a sticking limit (eqs 19-21).
// Departure (as the pair penalty): the normal interaction is a conservative
// penalty between material points, not the impulse of eqs 15-18. Its
// potential: for a point q of body A the smoothed volume fraction of the
// other body B at q,
//   phi_B(x_q) = sum_{p in B} V_p W(|x_q - x_p|),
// W the Wendland C2 kernel (radial, support H = 3 x the larger point spacing,
// normalised to 1), defines an equivalent overlap
//   delta_q = (phi_B(x_q) - phi*_B) / s_B,
// phi*_B the fraction that a point of A sees when the two lattices' faces
// touch (outer layers (d_A + d_B)/2 apart, points aligned) and s_B = |d phi /
// dz| there, so delta_q is the overlap of two flat faces to first order. The
// energy is E = sum_q c_q U(delta_q; d_q) over the points of both bodies, with
// U the pair penalty's potential (linear up to 0.3 d, barrier beyond; U = 0 for
// delta <= 0), d_q = (d_p(q) + d_B)/2 and c_q = V_q^(2/3) / (2 d_p^2): two
// touching faces of equal lattices then store the pair penalty's energy and
// feel its pressure kappa M delta / d_p. The force is -grad E: central pair
// forces between the points p, q of different bodies within H,
//   f_q = (a_q V_p + a_p V_q) (-W'(r) / r) (x_q - x_p),  a = c U'(delta) / s_B,
// so momentum and angular momentum are conserved to round-off and the energy
// in the time-continuous limit; the net force on a point follows grad phi,
// the normal of the other body's smoothed surface, so two lattices sliding
// across each other do not interlock: along a face aligned with the lattice
// the tangential gradient of phi is 0.06 % of the normal one at H = 3 d_p;
// a face inclined to the lattice axes is a row of terraces longer than one
// spacing, which H = 3 d_p still smooths (frictionless oblique sphere
// impact: spin omega R / v0 = 0.016, 0.29 at H = 2 d_p, 0.44 with the pair penalty).
#include <cstddef>
#include <cstdint>
#include <vector>

namespace needlesim::mpm {

// Wendland C2 kernel in 3D, W(r) = 21 / (2 pi H^3) (1 - q)^4 (1 + 4 q), q = r / H < 1.
struct WendlandC2 {
  double H = 0.0, c = 0.0;  // support radius (m), 21 / (2 pi H^3)
  explicit WendlandC2(double support = 1.0);
  double value(double r) const;
  // -W'(r) / r = 20 c / H^2 (1 - q)^3 (no division by r)
  double slopeOverR(double r) const;
  // bound on the spectral norm of the Hessian of W(|x|): max(|W''|, |W'| / r)
  double hessianBound(double r) const;
};

// Smoothed volume fraction of a half-space of points on a cubic lattice of
// spacing `spacing` (layers z = 0, -spacing, ...), seen from a point at height
// `height` above a lattice point, and its derivative -d phi / d z there.
struct LatticeFraction {
  double phi = 0.0, slope = 0.0;
};
LatticeFraction latticeFraction(const WendlandC2& W, double spacing, double height);

// The law's constants and scratch; owned by PairPenalty (penalty_contact.hpp).
struct DensityLaw {
  WendlandC2 kernel;
  int reach = 1;            // cells the search looks around a point's cell (H <= reach h, at most 3)
  double phiStar[2] = {0, 0}, slope[2] = {0, 0};  // per field body B: phi*_B and s_B (1/m)
  double spacing[2] = {0, 0};                     // per body: point spacing d_B (largest cbrt V0), m
  double invDp2 = 0.0;      // 1 / d_p^2 of the stiffness k = kappa M d_p (c_q = V_q^(2/3) invDp2 / 2)
  // Per candidate slot (8 doubles): phi, grad phi (3), Hessian bound, d phi / dt, pairs within H, pairs within
  // the contact distance (the friction's).
  std::vector<double> acc;
  std::vector<std::vector<double>> react;  // per thread t > 0: the same for the body-1 slots
  std::vector<double> a;       // per slot: c U'(delta) / s (0: not in contact)
  std::vector<double> normal;  // 3 per slot: the bodies' surface normal at the point (friction)
  std::vector<double> load;    // 2 per slot: normal load of all pairs, of the pairs within the contact distance (friction)
  struct Pair {
    std::uint32_t sp, sq;  // slots of p (body 0) and q (body 1)
    double c;              // -W'(r) / r at the step's start
  };
  std::vector<std::vector<Pair>> pairs;  // per thread: pairs within H at the step's start
  std::vector<double> phiEnd;            // per slot: phi at the step's end (energy report)
};

// The constants for two bodies: point radii (cbrt(V0) / 2), bodies, the
// global spacing d_p of the stiffness, the grid spacing h (H <= 3 h, else throws).
DensityLaw makeDensityLaw(const std::vector<double>& radius, const std::vector<std::uint8_t>& body, double dp, double h);

}  // namespace needlesim::mpm
