// Normal contact force at the end of the step (docs/models/explicit.md, "Contact stiffness").
//
// The penalty force of a node penetrating a rigid body by g along n is
//   f = k g^{n+1},   g^{n+1} = g^n - dt (v^{n+1/2} - v_b) . n,
// i.e. evaluated at the configuration the step produces (backward Euler on the contact
// spring, forward-increment kinematic contact in the limit k -> inf; Carpenter, Taylor &
// Katona 1991). Per node this is a scalar equation: with v0 the velocity the step would give
// with the force k g^n alone,
//   f = k (g^n - dt (v0 - v_b).n) ... solved: Delta f = -k dt vn0 / (1 + k dt dtAvg |n_free|^2 / m),
// clamped so that the total normal force stays compressive. An implicit spring only adds
// k dt^2 to the node's effective mass along n, so the central-difference limit of the element
// (Belytschko et al., box 6.1) is unchanged for any k: the contact needs no smaller step and
// the default k = 10 m / (cfl dt_stable)^2 leaves a penetration ~1/10 of the displacement the
// node's own element stiffness (~ m / dt_stable^2) would have under the same force.
// Friction keeps the explicit stick spring (SolverOptions::stickPenalty); its Coulomb cap is
// re-applied here with the normal force the step actually applies.
#include <algorithm>
#include <cmath>

#include "needlesim/engines/explicit/solver.hpp"

#include "needlesim/contact/coulomb.hpp"
#include "needlesim/contact/penalty.hpp"

namespace needlesim::explicit_fe {

using Eigen::Vector3d;

void ExplicitSolver::recordNormalContact(int n, int body, const Vector3d& normal, double k, double depth,
                                         const Vector3d& vb, double mu) {
  if (contactBody_[n] >= 0 && contactDepth_[n] >= depth) return;  // keep the deeper contact
  contactBody_[n] = body;
  contactK_[n] = k;
  contactDepth_[n] = depth;
  contactMu_[n] = mu;
  for (int i = 0; i < 3; ++i) {
    contactNrm_[static_cast<std::size_t>(n) * 3 + i] = normal[i];
    contactVb_[static_cast<std::size_t>(n) * 3 + i] = vb[i];
  }
}

double ExplicitSolver::contactStiffness(int node) const {
  const double dtPen = opt_.cfl * dtStable_;
  return dtPen > 0 ? contact::massPenalty(opt_.contactPenalty, mass_[node], dtPen) : 0.0;
}

void ExplicitSolver::addNormalContact(int node, const Vector3d& normal, double depth, const Vector3d& vb) {
  if (!(depth > 0)) return;
  const double k = contactStiffness(node);
  const Vector3d nrm = normal.normalized();
  recordNormalContact(node, 1, nrm, k, depth, vb);
  const double fn = contact::penaltyForce(k, depth);
  for (int i = 0; i < dim_; ++i) fcon_[static_cast<std::size_t>(node) * dim_ + i] += fn * nrm[i];
  extContactForce_ -= fn * nrm;
}

void ExplicitSolver::normalContactCorrection(double dt, double dtAvg) {
  const int d = dim_;
  // reactions: the explicit estimates of contactForces plus the corrections below
  NeedleLoads nl = needleStage_;
  for (std::size_t p = 0; p < planes_.size(); ++p) planes_[p].force = planeStage_[p];
  const Vector3d base = hasNeedle_ ? Vector3d(needle_.pose.tip - needle_.shape.length * needle_.pose.axis) : Vector3d::Zero();
  const double alpha = opt_.damping;
  const bool coh = !coh_.empty();
  for (int n = 0; n < nnode_; ++n) {
    contactFnApplied_[n] = 0.0;
    if (contactBody_[n] < 0) continue;
    const double m = mass_[n], k = contactK_[n];
    // cohesive seam lips keep the explicit penalty the wedge model was built with (solver.cpp)
    // (the sleeve's lips take the implicit correction: they must hold t_c >> E, cohesive_sleeve.hpp)
    if (sleeveRadius_ <= 0 && !cohPairOf_.empty() && cohPairOf_[n] >= 0) {
      contactFnApplied_[n] = contact::penaltyForce(k, contactDepth_[n]);
      continue;
    }
    const double* nrm = &contactNrm_[static_cast<std::size_t>(n) * 3];
    const double* vb = &contactVb_[static_cast<std::size_t>(n) * 3];
    double vn0 = 0.0, nFree2 = 0.0;
    for (int i = 0; i < d; ++i) {
      const std::size_t kk = static_cast<std::size_t>(n) * d + i;
      double v;
      if (dofGroup_[kk] >= 0) {
        v = groupVelocity_[dofGroup_[kk]];
      } else {
        const double f = fext_[kk] - fint_[kk] + fcon_[kk] - alpha * m * vHalf_[kk] + (coh ? fcoh_[kk] : 0.0);
        v = vHalf_[kk] + dtAvg * f / m;
        nFree2 += nrm[i] * nrm[i];
      }
      vn0 += (v - vb[i]) * nrm[i];
    }
    const double f0 = contact::penaltyForce(k, contactDepth_[n]);
    double df = -k * dt * vn0 / (1.0 + k * dt * dtAvg * nFree2 / m);
    df = std::max(df, -f0);  // the total normal force stays compressive
    contactFnApplied_[n] = f0 + df;
    for (int i = 0; i < d; ++i) fcon_[static_cast<std::size_t>(n) * d + i] += df * nrm[i];
    Vector3d dF = df * Vector3d(nrm[0], nrm[1], nrm[2]);  // change of the force on the node
    // Coulomb cone with the normal force actually applied (the friction of contactForces used k g^n)
    const int body = contactBody_[n];
    if (contactMu_[n] > 0 && (body == 0 || body >= 2)) {
      double* t = body == 0 ? &needleFt_[static_cast<std::size_t>(n) * 3] : &planeFt_[body - 2][static_cast<std::size_t>(n) * 3];
      const double tn = std::sqrt(t[0] * t[0] + t[1] * t[1] + t[2] * t[2]), lim = contactMu_[n] * (f0 + df);
      // slipping (at the cone of k g^n) or beyond the new cone: onto the cone of the applied force
      // (a slipping node stays on the cone: contact/coulomb.hpp's slip branch, limit / |t|, also where it grows)
      if (tn > lim || contact::coulombSlips(tn, contactMu_[n] * f0, 1e-9)) {
        const double sc = lim / tn;
        for (int i = 0; i < d; ++i) fcon_[static_cast<std::size_t>(n) * d + i] += (sc - 1.0) * t[i];
        if (body == 0)  // the needle's friction on the body (energy bookkeeping, solver.cpp)
          for (int i = 0; i < d; ++i) fconFriction_[static_cast<std::size_t>(n) * d + i] += (sc - 1.0) * t[i];
        dF += (sc - 1.0) * Vector3d(t[0], t[1], t[2]);
        for (int i = 0; i < 3; ++i) t[i] *= sc;
      }
    }
    if (body == 1) {
      extContactForce_ -= dF;
    } else if (body >= 2) {
      planes_[body - 2].force -= dF;
    } else if (body == 0) {
      // the needle's share of the body's contact force (energy bookkeeping, solver.cpp)
      for (int i = 0; i < d; ++i) fconNeedle_[static_cast<std::size_t>(n) * d + i] += dF[i];
      const double fnNew = std::max(f0 + df, 0.0);
      // the needle's axis at the node: its local path tangent for a path needle (path_needle.hpp)
      const Vector3d ax = contactAxis_.empty() ? needle_.pose.axis : Vector3d(&contactAxis_[static_cast<std::size_t>(n) * 3]);
      if (contactWedge_[n] != 0.0) dF += df * contactWedge_[n] * ax;  // wedged lip (solver.cpp)
      Vector3d x = Vector3d::Zero();
      for (int i = 0; i < d; ++i) x[i] = mesh_.X[static_cast<std::size_t>(n) * d + i] + u_[static_cast<std::size_t>(n) * d + i];
      nl.force -= dF;
      nl.moment += (x - base).cross(-dF);
      if (contactTip_[n]) nl.tip -= dF;
      nl.normal += fnNew - f0;
      nl.drive -= dF.dot(ax);
    }
  }
  if (hasNeedle_) {
    needle_.force = nl.force;
    needle_.moment = nl.moment;
    needle_.tipForce = nl.tip;
    needle_.normalForce = nl.normal;
    needle_.driveForce = nl.drive;
  }
}

}  // namespace needlesim::explicit_fe
