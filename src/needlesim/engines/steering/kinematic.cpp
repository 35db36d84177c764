#include "needlesim/engines/steering/kinematic.hpp"

#include <cmath>
#include <numbers>

namespace needlesim::steering {
namespace {

Mat3 hat(const Vec3& w) {
  Mat3 m;
  m << 0, -w.z(), w.y(), w.z(), 0, -w.x(), -w.y(), w.x(), 0;
  return m;
}

Mat3 rotZ(double a) {
  const double c = std::cos(a), s = std::sin(a);
  Mat3 r;
  r << c, -s, 0, s, c, 0, 0, 0, 1;
  return r;
}

// Integrates `len` of insertion with constant omega in n equal steps, recording each.
inline void runPhase(Pose& g, const Vec3& omega, double len, double sample_ds, std::span<Vec3> out,
                     int& count) {
  if (len <= 0) return;
  const int n = std::max(1, static_cast<int>(std::ceil(len / sample_ds - 1e-9)));
  const Pose step = twistExp(omega, len / n);
  for (int i = 0; i < n; ++i) {
    g.p += g.R * step.p;
    g.R = g.R * step.R;
    if (count < static_cast<int>(out.size())) out[count] = g.p;
    ++count;
  }
}

inline int phaseSteps(double len, double ds) {
  return len <= 0 ? 0 : std::max(1, static_cast<int>(std::ceil(len / ds - 1e-9)));
}

}  // namespace

// seed: Webster et al. 2006 eq (body twist), closed-form SE(3) exponential with v = e3:
// R = exp(w^ s), p = (I s + (1 - cos th)/|w|^2 w^ + (th - sin th)/|w|^3 w^2) e3, th = |w| s.
Pose twistExp(const Vec3& omega, double s) {
  Pose g;
  const double wn = omega.norm();
  const double th = wn * s;
  const Mat3 W = hat(omega);
  const Mat3 W2 = W * W;
  double A, B, C;  // R = I + A W + B W^2;  V = s I + B W + C W^2
  if (th < 1e-4) {  // series, error O(th^6)
    const double th2 = th * th;
    A = s * (1 - th2 / 6.0);
    B = s * s * (0.5 - th2 / 24.0);
    C = s * s * s * (1.0 / 6.0 - th2 / 120.0);
  } else {
    A = std::sin(th) / wn;
    B = (1 - std::cos(th)) / (wn * wn);
    C = (th - std::sin(th)) / (wn * wn * wn);
  }
  g.R = Mat3::Identity() + A * W + B * W2;
  const Mat3 V = s * Mat3::Identity() + B * W + C * W2;
  g.p = V.col(2);
  return g;
}

int kinematicSampleCount(const KinematicParams& par, std::span<const Control> plan) {
  int count = 1;
  for (const Control& c : plan) {
    if (c.duty_cycle > 0) {
      const int cycles = std::max(1, static_cast<int>(std::lround(c.length / c.cycle_length)));
      const double lc = c.length / cycles;
      count += cycles * (phaseSteps(c.duty_cycle * lc, par.sample_ds) +
                         phaseSteps((1 - c.duty_cycle) * lc, par.sample_ds));
    } else {
      count += phaseSteps(c.length, par.sample_ds);
    }
  }
  return count;
}

int simulateKinematic(const KinematicParams& par, const Pose& start, std::span<const Control> plan,
                      std::span<Vec3> out, Pose* end) {
  Pose g = start;
  int count = 0;
  if (!out.empty()) out[0] = g.p;
  ++count;
  const Vec3 bend(par.kappa, 0.0, 0.0);
  for (const Control& c : plan) {
    if (c.rotate != 0.0) g.R = g.R * rotZ(c.rotate);
    if (c.duty_cycle > 0) {
      // Duty cycling: per cycle, spin one full turn while inserting dc*lc, then
      // insert (1-dc)*lc with the bevel fixed. An integer number of cycles.
      const int cycles = std::max(1, static_cast<int>(std::lround(c.length / c.cycle_length)));
      const double lc = c.length / cycles;
      const double ls = c.duty_cycle * lc, lt = (1 - c.duty_cycle) * lc;
      const Vec3 spin(par.kappa, 0.0, 2 * std::numbers::pi / ls);
      for (int k = 0; k < cycles; ++k) {
        runPhase(g, spin, ls, par.sample_ds, out, count);
        runPhase(g, bend, lt, par.sample_ds, out, count);
      }
    } else {
      runPhase(g, Vec3(par.kappa, 0.0, c.spin), c.length, par.sample_ds, out, count);
    }
  }
  if (end) *end = g;
  return count < static_cast<int>(out.size()) ? count : static_cast<int>(out.size());
}

}  // namespace needlesim::steering
