#pragma once
// Modified Karnopp friction per unit length of needle in contact
// (seed 003 eq 3.23, per-length coefficients as in eq 5.1): the one implementation of the
// law, used by the lumped model (karnoppPerLength) and by the real-time engines' shaft
// coupling (the same branches through an explicit stick / hold / slip state, karnoppNext).
//
// Its coefficients are KarnoppFriction's (contact/friction_spec.hpp). D_p and D_n are used as
// given: the scenario reader's default is the continuous law, D = C + b static_band / 2; a
// KarnoppFriction built in code with D = 0 has no static friction.
#include "needlesim/contact/friction_spec.hpp"

namespace needlesim::contact {

// The sliding branches: v > 0 gives C_p + b_p v (eq 3.23, 4th branch), v < 0 gives
// -C_n + b_n v (1st branch: C_n sgn(v) + b_n v); `positive` picks the branch.
inline double karnoppSliding(const KarnoppFriction& f, bool positive, double v) {
  return positive ? f.C_p + f.b_p * v : -f.C_n + f.b_n * v;
}
// Its slope d/dv on the branch.
inline double karnoppDamping(const KarnoppFriction& f, bool positive) { return positive ? f.b_p : f.b_n; }
// The static limit of the branch: D_p, or -D_n (eq 3.23, 2nd and 3rd branches).
inline double karnoppStaticLimit(const KarnoppFriction& f, bool positive) { return positive ? f.D_p : -f.D_n; }

// Friction force per unit length on the needle, signed along the insertion
// axis: positive resists insertion (what a base sensor reads while inserting),
// negative resists retraction.
//   v >=  dv/2 :  C_p + b_p v                       (eq 3.23, 4th branch)
//   v <= -dv/2 : -C_n + b_n v                       (eq 3.23, 1st branch: C_n sgn(v) + b_n v)
//   |v| < dv/2 :  clamp(F_a, -D_n, D_p)             (static band; see docs/models/lumped-force.md)
// F_a is the force per length the tissue applies to the shaft while sticking.
inline double karnoppPerLength(const KarnoppFriction& f, double v, double F_a) {
  const double half = 0.5 * f.static_band;
  if (v >= half) return karnoppSliding(f, true, v);
  if (v <= -half) return karnoppSliding(f, false, v);
  if (F_a > f.D_p) return karnoppStaticLimit(f, true);
  if (F_a < -f.D_n) return karnoppStaticLimit(f, false);
  return F_a;
}

// Its partial derivatives d/dv and d/dF_a (eq 3.23 branch by branch): b_p or
// b_n while sliding, 0 in the static band; 1 along F_a inside the static
// limits, 0 once saturated. At a kink (|v| = dv/2, F_a = D_p or -D_n) the
// branch karnoppPerLength takes.
struct KarnoppSlope {
  double v = 0.0, applied = 0.0;
};
inline KarnoppSlope karnoppSlope(const KarnoppFriction& f, double v, double F_a) {
  const double half = 0.5 * f.static_band;
  if (v >= half) return {karnoppDamping(f, true), 0.0};
  if (v <= -half) return {karnoppDamping(f, false), 0.0};
  if (F_a > f.D_p || F_a < -f.D_n) return {};
  return {0.0, 1.0};
}

// The branch of eq 3.23 a contact point is on, for solvers that keep it from step to step
// (the real-time shaft coupling): sticking (F_a inside the static limits, moving with the
// needle), held at a static limit while |v| is inside the band, or sliding.
enum class KarnoppState : int { Stick, HoldPos, HoldNeg, SlipPos, SlipNeg };

// The next branch from the load per length F_a and the relative velocity v, with the
// thresholds of karnoppPerLength: stick -> hold beyond the static limit, hold -> slide
// once |v| reaches dv/2, slide -> stick back inside the band.
inline KarnoppState karnoppNext(KarnoppState s, const KarnoppFriction& f, double F_a, double v) {
  using S = KarnoppState;
  const double half = 0.5 * f.static_band;
  switch (s) {
    case S::Stick: return F_a > f.D_p ? S::HoldPos : (F_a < -f.D_n ? S::HoldNeg : S::Stick);
    case S::HoldPos: return v >= half ? S::SlipPos : (v <= 0.0 ? S::Stick : s);
    case S::HoldNeg: return v <= -half ? S::SlipNeg : (v >= 0.0 ? S::Stick : s);
    case S::SlipPos: return v < half ? S::Stick : s;
    case S::SlipNeg: return v > -half ? S::Stick : s;
  }
  return s;
}

}  // namespace needlesim::contact
