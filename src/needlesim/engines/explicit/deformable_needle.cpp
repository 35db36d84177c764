#include "needlesim/engines/explicit/deformable_needle.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "needlesim/core/error.hpp"
#include "needlesim/engines/explicit/solver.hpp"
#include "needlesim/needle/beam_element.hpp"

namespace needlesim::explicit_fe {

using Eigen::Vector3d;

namespace {
// Small-deflection limit of the Euler-Bernoulli beam (slope ~ 20 deg: sin x / x within 2 %).
constexpr double kMaxSlope = 0.35;
constexpr double kMinLateralSpeed = 1e-3;  // m/s
}  // namespace

double ExplicitSolver::needleLateralStiffness(const Vector3d& e) const {
  double k = 0.0;
  for (int n = 0; n < nnode_; ++n) {
    if (contactBody_[n] != 0) continue;
    const double* c = &contactNrm_[static_cast<std::size_t>(n) * 3];
    const double ce = c[0] * e[0] + c[1] * e[1] + c[2] * e[2];
    k += contactK_[n] * ce * ce;
  }
  return k;
}

needle::BeamSolution cantileverFromResultant(double EI, double length, int elements, double force, double moment) {
  needle::StraightBeam b;
  b.EI = EI;
  b.length = length;
  b.elements = elements;
  const double h = length / elements;
  std::vector<needle::NodalLoad> loads;
  double a = length;
  if (force != 0.0) a = std::clamp(moment / force, 0.0, length);
  if (force != 0.0) {
    // point load at a: consistent Hermite loads P N(xi) (beam_element.hpp), exact nodal values
    const int j = std::min(static_cast<int>(a / h), elements - 1);
    const double xi = a / h - j;
    const needle::Vec4 N = needle::hermiteN(xi, h);
    loads.push_back({j, force * N[0], force * N[1]});
    loads.push_back({j + 1, force * N[2], force * N[3]});
  }
  loads.push_back({elements, 0.0, moment - a * force});  // the rest of the moment as a tip couple
  return needle::solveStraightBeam(b, loads);
}

DeformableNeedle::DeformableNeedle(const needle::Section& section, double length, int dim, int elements)
    : EI_(section.EI()), L_(length), dim_(dim), ne_(elements) {
  if (!(EI_ > 0) || !(L_ > 0) || ne_ < 1)
    throw Error("model.explicit.needle_model beam needs needle.youngs_modulus > 0, needle.outer_diameter > 0 and "
                "needle.length > 0");
  for (int p = 0; p < 2; ++p)
    w_[p].assign(ne_ + 1, 0.0), th_[p].assign(ne_ + 1, 0.0), vw_[p].assign(ne_ + 1, 0.0), vt_[p].assign(ne_ + 1, 0.0);
}

void DeformableNeedle::update(RigidNeedle& n, const ExplicitSolver& solver, const Vector3d& base, const Vector3d& axis,
                              const Vector3d& bevelSide, double scale) {
  Vector3d e[2];
  e[0] = (bevelSide - bevelSide.dot(axis) * axis).normalized();
  e[1] = axis.cross(e[0]);
  // The solver's moment is about the base of the pose it used (the last one set here): move it to the clamp.
  const Vector3d baseUsed = started_ ? Vector3d(lastTip_ - L_ * lastAxis_) : base;
  const Vector3d F = n.force * scale, M = (n.moment + (baseUsed - base).cross(n.force)) * scale;
  const double C = L_ * L_ * L_ / (3.0 * EI_);
  // Damped follower (dynamic relaxation of the needle, see the header): u'' = w0^2 (u_beam - u) - 2 w0 u'.
  // A pose jump du changes u_beam by -C K du at once (penalty), so the loop's highest frequency is
  // w0 sqrt(1 + C K); w0 = 1 / (dt sqrt(1 + 2 C K)) keeps it at w dt < 0.71 (central differences: < 2).
  const double dt = solver.timeStep() > 0 ? solver.timeStep() : solver.stableTimeStep();
  double ck = 0.0;
  for (int p = 0; p < (dim_ == 3 ? 2 : 1); ++p) ck = std::max(ck, C * solver.needleLateralStiffness(e[p]) * scale);
  const double w0 = 1.0 / (dt * std::sqrt(1.0 + 2.0 * ck)), a = w0 * dt;
  double wTip[2] = {0, 0}, thTip[2] = {0, 0}, residual = 0.0;
  e_[0] = e[0], e_[1] = dim_ == 3 ? e[1] : Vector3d::Zero();
  for (int p = 0; p < (dim_ == 3 ? 2 : 1); ++p) {
    const auto s = cantileverFromResultant(EI_, L_, ne_, F.dot(e[p]), M.dot(axis.cross(e[p])));
    residual = std::max(residual, std::abs(s.w.back() - w_[p].back()));
    target_[p] = s.w.back();
    // kinetic damping (dynamic relaxation): moving away from the beam solution, restart at rest, so
    // momentum gathered while the contact was soft cannot carry the pose past it when it stiffens
    if (vw_[p].back() * (s.w.back() - w_[p].back()) < 0.0) {
      std::fill(vw_[p].begin(), vw_[p].end(), 0.0);
      std::fill(vt_[p].begin(), vt_[p].end(), 0.0);
    }
    for (int i = 0; i <= ne_; ++i) {
      // central differences, damping semi-implicit (v at the half steps)
      vw_[p][i] = ((1.0 - a) * vw_[p][i] + dt * w0 * w0 * (s.w[i] - w_[p][i])) / (1.0 + a);
      vt_[p][i] = ((1.0 - a) * vt_[p][i] + dt * w0 * w0 * (s.theta[i] - th_[p][i])) / (1.0 + a);
    }
    // the tip moves sideways no faster than the needle advances (1 mm/s at rest): a pose jump the
    // penalty contact cannot follow would push the tissue nodes through the wall
    const double vmax = std::max(std::abs(n.velocity), kMinLateralSpeed), vTip = std::abs(vw_[p].back());
    const double cap = vTip > vmax ? vmax / vTip : 1.0;
    for (int i = 0; i <= ne_; ++i) {
      vw_[p][i] *= cap, vt_[p][i] *= cap;
      w_[p][i] += dt * vw_[p][i];
      th_[p][i] += dt * vt_[p][i];
    }
    wTip[p] = w_[p].back();
    thTip[p] = th_[p].back();
  }
  residual_ = residual;
  if (n.nodesInContact > 0) residualSum_ += residual, ++residualCount_;
  // residual averaged over the follower's time 1 / w0: single-step spikes of the contact force (a seam
  // node snapping open) are filtered out by the follower and do not count as divergence
  residualAvg_ += std::min(1.0, a) * (residual - residualAvg_);
  const double slope = std::hypot(thTip[0], thTip[1]), wAbs = std::hypot(wTip[0], wTip[1]);
  if (!std::isfinite(slope) || !std::isfinite(residual) || slope > kMaxSlope || wAbs > 0.25 * L_ ||
      residualAvg_ > 0.25 * L_)
    throw SolverError(fmt::format(
        "explicit FE stopped at t = {:.6g} s (step {}): the deformable needle (model.explicit.needle_model: beam) left "
        "the small-deflection range or did not converge: tip slope {:.3g} rad (limit {:.2g} rad), tip deflection "
        "{:.3g} mm (limit L/4 = {:.3g} mm), beam solution minus applied deflection {:.3g} mm averaged over the "
        "follower's time (limit L/4). Remedy: a stiffer or shorter needle (needle.youngs_modulus, needle.length), a "
        "slower insertion, or needle_model: rigid",
        solver.time(), solver.steps(), slope, kMaxSlope, wAbs * 1e3, 0.25 * L_ * 1e3, residualAvg_ * 1e3));
  Vector3d ax = axis + thTip[0] * e[0] + thTip[1] * e[1];
  ax.normalize();
  n.pose.tip = base + L_ * axis + wTip[0] * e[0] + wTip[1] * e[1];
  n.pose.axis = ax;
  n.pose.bevelSide = (bevelSide - bevelSide.dot(ax) * ax).normalized();
  lastTip_ = n.pose.tip;
  lastAxis_ = ax;
  started_ = true;
}

}  // namespace needlesim::explicit_fe
