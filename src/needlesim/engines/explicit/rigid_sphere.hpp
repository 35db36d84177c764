#pragma once
// Analytic rigid sphere obstacle for the explicit solver (tests; Hertz
// indentation, docs/validation/fe.md). Frictionless node-to-sphere penalty with
// the solver's stiffness k = penalty m_a / (cfl dt_stable)^2 (solver.cpp
// contactForces). Hook: the forces go through ExplicitSolver::setExternalForce
// before each step(), so they act at the same configuration as the internal
// forces (central difference), and their work is booked as external work.
#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <vector>

#include "needlesim/engines/explicit/solver.hpp"

namespace needlesim::explicit_fe {

struct RigidSphere {
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  double radius = 1.0;
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();
  double penalty = 0.2;  // as SolverOptions::contactPenalty
  double cfl = 0.9;      // as SolverOptions::cfl
  // results of the last apply()
  Eigen::Vector3d force = Eigen::Vector3d::Zero();  // reaction on the sphere (from the body)
  int nodesInContact = 0;
  std::vector<int> contactNodes;
  double maxPenetration = 0.0;

  // Sets the contact force of every node of `s` (overwrites its external forces on contacting nodes,
  // zeroes them on the others: use for bodies without other external loads).
  void apply(ExplicitSolver& s) {
    const int d = s.dim();
    const auto& X = s.mesh().X;
    const auto& u = s.displacement();
    const double dt = cfl * s.stableTimeStep();
    const double pen = dt > 0 ? penalty / (dt * dt) : 0.0;
    force.setZero();
    nodesInContact = 0;
    contactNodes.clear();
    maxPenetration = 0.0;
    for (int n = 0; n < s.mesh().nodes(); ++n) {
      Eigen::Vector3d x = Eigen::Vector3d::Zero();
      for (int i = 0; i < d; ++i) x[i] = X[static_cast<std::size_t>(n) * d + i] + u[static_cast<std::size_t>(n) * d + i];
      Eigen::Vector3d r = x - centre;
      const double dist = r.norm();
      const double gap = dist - radius;
      if (gap >= 0 || dist == 0) {
        for (int i = 0; i < d; ++i) s.setExternalForce(n, i, 0.0);
        continue;
      }
      const Eigen::Vector3d f = (-gap * pen * s.nodalMass()[n] / dist) * r;
      for (int i = 0; i < d; ++i) s.setExternalForce(n, i, f[i]);
      force -= f;
      ++nodesInContact;
      contactNodes.push_back(n);
      maxPenetration = std::max(maxPenetration, -gap);
    }
  }
  void move(double dt) { centre += dt * velocity; }
};

}  // namespace needlesim::explicit_fe
