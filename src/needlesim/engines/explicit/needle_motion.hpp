#pragma once
// Rigid needle motion of the explicit engine (docs/models/explicit.md, "Needle rotation"):
// translation along the axis and rotation about it (the profile's axial `rotate` segments,
// insertion/motion_profile.hpp). The surface velocity at a point x is
//   v_b(x) = v e_a + omega e_a x (x - x_tip),
// which the contact uses for friction (relative sliding) and for the end-of-step normal force.
#include <Eigen/Core>
#include <Eigen/Geometry>

#include "needlesim/needle/surface_mesh.hpp"

namespace needlesim::explicit_fe {

struct RigidNeedle;

// Velocity of the needle's material point at x.
Eigen::Vector3d needleSurfaceVelocity(const RigidNeedle& n, const Eigen::Vector3d& x);
// Moves the needle over dt: the tip along the axis, the bevel side about the axis.
void advanceNeedle(RigidNeedle& n, double dt);
// Bevel direction for an orientation angle about the axis: cos(a) e1 + sin(a) e2 in 3D; in a
// 2D plane-strain model only the in-plane sides exist, +-e1 by the sign of cos(a).
Eigen::Vector3d bevelSideAt(double angle, const Eigen::Vector3d& e1, const Eigen::Vector3d& e2, int dim);

}  // namespace needlesim::explicit_fe
