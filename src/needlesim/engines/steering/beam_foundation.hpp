#pragma once
// Beam-on-elastic-foundation steering model (the mechanics-based model seed 002
// section 6 calls for as future work). The needle is an Euler-Bernoulli beam
// (needle/beam_element.hpp) clamped at the entry point by the support sheath
// (seed 002 section 2.4.2), supported by a Winkler foundation K_T per unit
// length (seed 002 eq 13) only along the channel it has already cut, and
// loaded at the tip by the bevel loads Q and M (seed 002 eqs 25-26).
// Large rotations along the path: the deflection is solved as a small deviation
// w from the cut channel in the channel's own (parallel-transported) frame, with
// the channel curvature as a natural-curvature load; two transverse directions
// make it 3D. The channel grows by one element per increment: its new node is
// where the tip lands. Details: docs/models/steering.md.
#include <span>
#include <vector>

#include <Eigen/Core>

#include "needlesim/engines/steering/kinematic.hpp"
#include "needlesim/needle/banded.hpp"

namespace needlesim::steering {

struct BeamFoundationParams {
  double EI = 0.0;           // N m^2
  double K_T = 0.0;          // N/m^2, foundation stiffness per unit length
  double Q = 0.0;            // N, transverse tip load along +y of the bevel frame (Fig 13)
  double M = 0.0;            // N m, tip moment (Fig 13, counter-clockwise x -> y)
  double axial_force = 0.0;  // N, tension positive (a compressive tip load P is -P)
  double increment = 1e-3;   // m, insertion per increment = element length
  double max_length = 0.2;   // m, capacity reserved up front
};

// Steady-state curvature of the model in the limit of small increments:
// kappa = (M + Q / lambda) / EI, lambda = (K_T / (4 EI))^(1/4), towards +y of the
// bevel frame (negative: towards -y). Derived from Hetenyi's semi-infinite beam
// with the tip kept on the channel it cuts (docs/models/steering.md).
double beamFoundationSteadyCurvature(double EI, double K_T, double Q, double M);

class BeamFoundationModel {
 public:
  explicit BeamFoundationModel(const BeamFoundationParams& p);
  // Starts at the entry pose: p = entry point, R.col(2) = insertion axis, R.col(1) =
  // bevel +y at bevel angle 0; `bevel` = initial axial rotation of the bevel (rad).
  void reset(const Pose& entry, double bevel = 0.0);
  void rotateBevel(double angle) { bevel_ += angle; }
  void setLoads(double Q, double M) {
    p_.Q = Q;
    p_.M = M;
  }
  // Inserts one increment and solves the equilibrium. Never allocates.
  void advance();
  int elements() const { return n_; }
  double insertedLength() const { return n_ * p_.increment; }
  const Vec3& tip() const { return X_[n_]; }
  Vec3 tipDirection() const { return T_[n_]; }
  // Tip path = channel nodes 0..n.
  std::span<const Vec3> path() const { return {X_.data(), static_cast<size_t>(n_ + 1)}; }
  // Deformed needle inside the tissue (node positions), into out (resized).
  void shape(std::vector<Vec3>& out) const;

 private:
  BeamFoundationParams p_;
  double bevel_ = 0.0;
  int n_ = 0;                       // elements inserted
  std::vector<Vec3> X_, T_, N1_, N2_;  // channel nodes: position, incoming tangent, normals
  std::vector<double> k1_, k2_;     // channel curvature at nodes (components in the node frame)
  std::vector<double> rhs1_, rhs2_;  // forward-substituted loads (L^-1 f)
  mutable needle::BandedSPD<3> K_;
  Eigen::Matrix4d kb_, kbf_;
};

}  // namespace needlesim::steering
