#pragma once
// Analytic rigid sphere obstacle for the explicit solver (tests; Hertz
// indentation, docs/validation/fe.md). Frictionless node-to-sphere contact with
// the solver's own normal contact (ExplicitSolver::addNormalContact: stiffness
// contact_penalty m_a / (cfl dt_stable)^2, force at the end of the step,
// contact_normal.cpp), registered before each step(); the force the step
// applied is ExplicitSolver::externalContactForce() after it.
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
  // results of the last apply()
  int nodesInContact = 0;
  std::vector<int> contactNodes;
  double maxPenetration = 0.0;

  // Registers the contact of every penetrating node of `s` for the next step.
  void apply(ExplicitSolver& s) {
    const int d = s.dim();
    const auto& X = s.mesh().X;
    const auto& u = s.displacement();
    nodesInContact = 0;
    contactNodes.clear();
    maxPenetration = 0.0;
    for (int n = 0; n < s.mesh().nodes(); ++n) {
      Eigen::Vector3d x = Eigen::Vector3d::Zero();
      for (int i = 0; i < d; ++i) x[i] = X[static_cast<std::size_t>(n) * d + i] + u[static_cast<std::size_t>(n) * d + i];
      Eigen::Vector3d r = x - centre;
      const double dist = r.norm();
      const double gap = dist - radius;
      if (gap >= 0 || dist == 0) continue;
      s.addNormalContact(n, r / dist, -gap, velocity);
      ++nodesInContact;
      contactNodes.push_back(n);
      maxPenetration = std::max(maxPenetration, -gap);
    }
  }
  void move(double dt) { centre += dt * velocity; }
};

}  // namespace needlesim::explicit_fe
