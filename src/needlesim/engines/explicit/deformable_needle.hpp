#pragma once
// Deformable needle of the explicit engine (model.explicit.needle_model: beam; docs/models/explicit.md,
// "Deformable needle"): an Euler-Bernoulli cantilever clamped at the needle base, which follows the
// insertion profile, loaded by the tissue's contact resultant on the needle (force and moment about
// the base, collected by the solver each step) and solved quasi-statically once per explicit step with
// the shared beam element and banded solver (needle/beam_solver.hpp). The contact surface is the
// rigid needle's shape placed at the deflected tip, along the deflected tip axis (a straight shaft
// along the tip tangent: the first approximation the docs describe).
//
// Load model: per bending plane (lateral unit e), the lateral force F_e and the moment M_e about the
// clamped base fix the line of action a = M_e / F_e of the resultant; F_e acts as a point load at a
// (clamped to [0, L], consistent Hermite loads, exact nodal values for a cubic beam) and what is left,
// M_e - a F_e, as a couple at the tip. Statically exact; where the contact is one patch (the inserted
// part near the tip) the deflection is that of the patch's resultant.
// Coupling: the pose lags one step behind the loads, and a pose jump du changes the contact force
// at once by the penalty stiffness K of the nodes in contact (C K ~ 1e3-1e4 for a soft needle,
// C = L^3 / (3 EI) the tip compliance), so a plain fixed-point update diverges and under-relaxation
// stable against K lags by ~C K steps. The applied nodal deflections u follow the beam solution as
// a critically damped oscillator (dynamic relaxation of a mass-scaled needle),
// u'' = w0^2 (u_beam - u) - 2 w0 u', w0 = 1 / (dt sqrt(1 + 2 C K)): lag ~sqrt(C K) steps, loop
// frequency < 0.71 / dt; kinetic damping (restart at rest when moving away from u_beam) and a
// lateral tip speed capped at the insertion speed. Stops with SolverError when the slope leaves
// small deflections or the averaged residual grows (docs/models/explicit.md, "Deformable needle").
#include <Eigen/Core>
#include <vector>

#include "needlesim/needle/beam_solver.hpp"
#include "needlesim/needle/section.hpp"

namespace needlesim::explicit_fe {

struct RigidNeedle;
class ExplicitSolver;

// One bending plane of a clamped cantilever of length L: lateral force F and moment M about the
// clamped end (both in the plane, M = a F for a force at distance a), as described above.
needle::BeamSolution cantileverFromResultant(double EI, double length, int elements, double force, double moment);

class DeformableNeedle {
 public:
  // dim 2: one bending plane (the insertion plane); 3: two.
  DeformableNeedle(const needle::Section& section, double length, int dim, int elements = 20);

  // Once per explicit step, before it: loads from n.force / n.moment (the last step's reaction, per
  // unit thickness times `scale`), solves the beam with the base clamped at `base` along `axis`
  // (undeflected), relaxes and sets n.pose (tip, axis, bevelSide from the rigid `bevelSide`).
  void update(RigidNeedle& n, const ExplicitSolver& solver, const Eigen::Vector3d& base, const Eigen::Vector3d& axis,
              const Eigen::Vector3d& bevelSide, double scale);

  // Applied (relaxed) tip deflection and slope along a unit direction e across the needle (e.g. the
  // insertion frame's lateral), m and rad; the beam's tip deflection under the last step's loads along e.
  double tipDeflectionAlong(const Eigen::Vector3d& e) const { return tipValueAlong(w_, e); }
  double tipSlopeAlong(const Eigen::Vector3d& e) const { return tipValueAlong(th_, e); }
  double targetDeflectionAlong(const Eigen::Vector3d& e) const { return target_[0] * e_[0].dot(e) + target_[1] * e_[1].dot(e); }
  double EI() const { return EI_; }
  // |beam tip deflection under the last step's loads - applied| at the tip in the last update and its
  // mean over the updates in contact.
  double residual() const { return residual_; }
  double meanResidual() const { return residualCount_ ? residualSum_ / residualCount_ : 0.0; }

 private:
  double EI_, L_;
  int dim_, ne_;
  std::vector<double> w_[2], th_[2];    // applied nodal deflection and slope per plane
  std::vector<double> vw_[2], vt_[2];  // their rates (the damped follower)
  Eigen::Vector3d e_[2] = {Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()};  // the planes' lateral directions
  double target_[2] = {0.0, 0.0};      // beam tip deflection per plane under the last loads
  double tipValueAlong(const std::vector<double> (&v)[2], const Eigen::Vector3d& e) const {
    double s = 0.0;
    for (int p = 0; p < 2; ++p)
      if (!v[p].empty()) s += v[p].back() * e_[p].dot(e);
    return s;
  }
  Eigen::Vector3d lastTip_ = Eigen::Vector3d::Zero(), lastAxis_ = Eigen::Vector3d::Zero();
  bool started_ = false;
  double residual_ = 0.0, residualSum_ = 0.0, residualAvg_ = 0.0;
  long residualCount_ = 0;
};

}  // namespace needlesim::explicit_fe
