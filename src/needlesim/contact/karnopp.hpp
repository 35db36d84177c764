#pragma once
// Modified Karnopp friction per unit length of needle in contact
// (seed 003 eq 3.23, per-length coefficients as in eq 5.1).
#include "needlesim/contact/friction_spec.hpp"

namespace needlesim::contact {

// Friction force per unit length on the needle, signed along the insertion
// axis: positive resists insertion (what a base sensor reads while inserting),
// negative resists retraction.
//   v >=  dv/2 :  C_p + b_p v                       (eq 3.23, 4th branch)
//   v <= -dv/2 : -C_n + b_n v                       (eq 3.23, 1st branch: C_n sgn(v) + b_n v)
//   |v| < dv/2 :  clamp(F_a, -D_n, D_p)             (static band; see docs/models/lumped-force.md)
// F_a is the force per length the tissue applies to the shaft while sticking.
inline double karnoppPerLength(const FrictionSpec& f, double v, double F_a) {
  const double half = 0.5 * f.static_band;
  if (v >= half) return f.C_p + f.b_p * v;
  if (v <= -half) return -f.C_n + f.b_n * v;
  if (F_a > f.D_p) return f.D_p;
  if (F_a < -f.D_n) return -f.D_n;
  return F_a;
}

// Its partial derivatives d/dv and d/dF_a (eq 3.23 branch by branch): b_p or
// b_n while sliding, 0 in the static band; 1 along F_a inside the static
// limits, 0 once saturated. At a kink (|v| = dv/2, F_a = D_p or -D_n) the
// branch karnoppPerLength takes.
struct KarnoppSlope {
  double v = 0.0, applied = 0.0;
};
inline KarnoppSlope karnoppSlope(const FrictionSpec& f, double v, double F_a) {
  const double half = 0.5 * f.static_band;
  if (v >= half) return {f.b_p, 0.0};
  if (v <= -half) return {f.b_n, 0.0};
  if (F_a > f.D_p || F_a < -f.D_n) return {};
  return {0.0, 1.0};
}

}  // namespace needlesim::contact
