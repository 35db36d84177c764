#pragma once
// CFEMP (seed 000 eqs 22-24): the rigid needle's surface as the triangles of
// the FE needle of section 4.3 in the needle's own frame (tip at the origin,
// axis x, sharp point at -R y), with a uniform bucket grid for the nearest
// facet of a material point. The contact itself: MpmSolver::surfaceContact
// (cfemp_contact.cpp).
#include <Eigen/Core>
#include <cstdint>
#include <limits>
#include <vector>

#include "needlesim/engines/mpm/rigid_body.hpp"

namespace needlesim::mpm {

// The point of triangle (a, b, c) closest to p.
Vec3 closestOnTriangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);

struct NeedleSurface {
  std::vector<Vec3> a, b, c, n;       // triangle corners and outward normals
  std::vector<std::uint8_t> tip;      // 1: tip face (force split)
  Vec3 lo = Vec3::Zero();
  double cell = 0.0, reach = 0.0;
  int dim[3] = {0, 0, 0};
  std::vector<int> start, items;      // triangles per bucket (CSR)

  // The surface of needle rb: facets of about d_e (rb.elementSize, else the
  // particle spacing dp); the buckets reach the gap rule's (d_e + gap) plus
  // half a grid cell h for the motion.
  void build(const RigidBody& rb, double dp, double gap, double h);
  struct Hit {
    int facet = -1;
    double gap = std::numeric_limits<double>::infinity();
  };
  Hit nearest(const Vec3& xl, double radius) const;
};

}  // namespace needlesim::mpm
