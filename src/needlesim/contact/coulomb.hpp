#pragma once
// Coulomb friction as the contact engines apply it (docs/models/contact.md):
// a trial tangential force, impulse or sticking force of magnitude s is kept
// while it lies inside the cone s <= mu N (stick) and scaled back onto the
// cone otherwise (slip), along the trial's own direction. One return map for
//   - the explicit FE's stick spring (seed 001: mu 0.3 on the needle walls,
//     elastic stick predictor then the return map; stickSpringFriction),
//   - the MPM grid and surface contacts (seed 000 eqs 19-21: the sticking
//     impulse m |v_t| limited by mu times the normal impulse; coulombScale),
//   - the MPM pair friction of the penalty contact (seed 000 eqs
//     19-21 with forces: m_r |v_t| / dt limited by mu f_N; coulombPair).
// Each law comes with its partial derivatives with respect to the trial and
// the normal force (tests/contact check them by finite differences). At the
// kink s = mu N the stick side is returned. Header-only, inline and
// allocation-free: these sit in the solvers' contact loops.
#include <Eigen/Core>
#include <algorithm>
#include <cmath>

namespace needlesim::contact {

// The factor that takes a trial of magnitude `trial` (>= 0) onto the Coulomb
// limit `limit` = mu N (>= 0): 1 while it sticks, limit / trial while it slips
// (a zero trial sticks). For trial > 0 it equals min(trial, limit) / trial to
// the bit (x / x is exactly 1).
constexpr double coulombScale(double trial, double limit) noexcept { return trial > limit ? limit / trial : 1.0; }

// Whether a tangential force of magnitude t is slipping: on the cone of limit
// mu N (t > 0), to the relative tolerance rtol. A slipping contact stays on
// the cone when N changes: scale limit_new / t (explicit/contact_normal.cpp).
constexpr bool coulombSlips(double t, double limit, double rtol) noexcept { return t > 0.0 && t >= limit * (1.0 - rtol); }

// The magnitude of the friction force, min(trial, limit) = coulombScale * trial.
constexpr double coulombMagnitude(double trial, double limit) noexcept { return std::min(limit, trial); }

// Partial derivatives of a law of the trial magnitude and the normal force N
// (limit = mu N): d/dtrial and d/dN.
struct CoulombSlope {
  double trial = 0.0, normal = 0.0;
};

// Of coulombScale(trial, mu N): stick 0, 0; slip -mu N / trial^2, mu / trial.
constexpr CoulombSlope coulombScaleSlope(double trial, double mu, double normal) noexcept {
  const double limit = mu * normal;
  if (!(trial > limit)) return {};
  return {-limit / (trial * trial), mu / trial};
}

// Of coulombMagnitude(trial, mu N): stick 1, 0; slip 0, mu.
constexpr CoulombSlope coulombMagnitudeSlope(double trial, double mu, double normal) noexcept {
  if (trial > mu * normal) return {0.0, mu};
  return {1.0, 0.0};
}

// The return map of a trial tangential force vector t: t coulombScale(|t|, limit).
inline Eigen::Vector3d coulombReturnMap(const Eigen::Vector3d& t, double limit) {
  return t * coulombScale(t.norm(), limit);
}

// Its Jacobian d t_out / d t (stick: I; slip: mu N / |t| (I - e e^T), e = t / |t|)
// and d t_out / dN (stick: 0; slip: mu e).
inline Eigen::Matrix3d coulombReturnMapJacobian(const Eigen::Vector3d& t, double mu, double normal) {
  const double s = t.norm();
  if (!(s > mu * normal)) return Eigen::Matrix3d::Identity();
  const Eigen::Vector3d e = t / s;
  return (mu * normal / s) * (Eigen::Matrix3d::Identity() - e * e.transpose());
}
inline Eigen::Vector3d coulombReturnMapNormalSlope(const Eigen::Vector3d& t, double mu, double normal) {
  const double s = t.norm();
  if (!(s > mu * normal)) return Eigen::Vector3d::Zero();
  return (mu / s) * t;
}

// The explicit solver's friction (seed 001, mu 0.3 on the walls): a stick
// spring whose force tOld of the last step (its part along the unit normal n
// removed: the contact normal turns) takes the increment -kdt v_t over the
// step, kdt = k_stick dt, v_t the tangential part of the relative velocity
// vRel; then the return map onto mu N = limit. kdt = 0 is a rigid-plastic
// drag that only keeps (and caps) the force it had.
inline Eigen::Vector3d stickSpringFriction(const Eigen::Vector3d& tOld, const Eigen::Vector3d& n,
                                           const Eigen::Vector3d& vRel, double kdt, double limit) {
  const Eigen::Vector3d vt = vRel - vRel.dot(n) * n;
  Eigen::Vector3d t = tOld;
  t -= t.dot(n) * n;
  t -= kdt * vt;                     // elastic stick predictor (slip increment over the step)
  return coulombReturnMap(t, limit);  // onto the Coulomb cone
}

// Coulomb friction of an MPM pair of points (seed 000 eqs 19-21), added to f
// (the force on p): the sliding velocity vp - vq with its part along the unit
// normal m removed, v_t, the sticking force m_r |v_t| / dt (the force that
// stops the pair's reduced mass m_r within the step, eq 19) limited by
// mu fN (eqs 20-21), opposite v_t. Returns the friction work over the step
// (J, >= 0). Used by the MPM pair penalty (penalty_contact.hpp).
inline double coulombPair(const double* m, double fN, const double* vp, const double* vq, double mr, double mu,
                          double dt, double* f) {
  double vt[3] = {vp[0] - vq[0], vp[1] - vq[1], vp[2] - vq[2]};
  const double vn = vt[0] * m[0] + vt[1] * m[1] + vt[2] * m[2];
  for (int c = 0; c < 3; ++c) vt[c] -= vn * m[c];
  const double st = std::sqrt(vt[0] * vt[0] + vt[1] * vt[1] + vt[2] * vt[2]);
  if (!(st > 0.0)) return 0.0;
  const double ft = coulombMagnitude(mr * st / dt, mu * fN);
  for (int c = 0; c < 3; ++c) f[c] -= ft * vt[c] / st;
  return ft * st * dt;
}

// Derivatives of coulombPair's force with respect to the sliding velocity
// w = vp - vq (3x3, dF(i, j) = df_i / dw_j) and to fN (3): with P = I - m m^T,
// v_t = P w, e = v_t / |v_t|: stick f = -m_r/dt v_t, so dF = -m_r/dt P and
// 0 along fN; slip f = -mu fN e, so dF = -mu fN / |v_t| (I - e e^T) P and
// -mu e along fN. Zero where the pair does not slide (|v_t| = 0).
inline void coulombPairSlope(const double* m, double fN, const double* vp, const double* vq, double mr, double mu,
                             double dt, Eigen::Matrix3d& dF, Eigen::Vector3d& dN) {
  const Eigen::Vector3d mn(m[0], m[1], m[2]);
  const Eigen::Matrix3d P = Eigen::Matrix3d::Identity() - mn * mn.transpose();
  const Eigen::Vector3d vt = P * Eigen::Vector3d(vp[0] - vq[0], vp[1] - vq[1], vp[2] - vq[2]);
  const double st = vt.norm();
  dF.setZero();
  dN.setZero();
  if (!(st > 0.0)) return;
  if (!(mr * st / dt > mu * fN)) {
    dF = -(mr / dt) * P;
    return;
  }
  const Eigen::Vector3d e = vt / st;
  dF = -(mu * fN / st) * (Eigen::Matrix3d::Identity() - e * e.transpose()) * P;
  dN = -mu * e;
}

}  // namespace needlesim::contact
