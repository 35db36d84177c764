#pragma once
// Lattice spheres and per-body sums shared by the MPM sphere-impact tests
// (test_mpm_penalty_spheres.cpp: head-on, test_mpm_penalty_oblique.cpp:
// oblique).
#include <cmath>
#include <cstddef>

#include <Eigen/Dense>

#include "needlesim/engines/mpm/mpm_solver.hpp"

namespace needlesim::mpm::test {

// Fills a sphere with points on a lattice of spacing dp centred on the
// sphere's centre (points at c + (i + 1/2) dp), keeping the points whose
// centre lies inside; each point has the volume dp^3. Along the axes the
// outermost points then lie at R - dp/2 (for R / dp an integer), so the
// points' volumes (diameter dp, the penalty's contact distance) reach R at
// the poles. Returns the number of points.
inline std::size_t addSphere(MpmSolver& s, const Vec3& c, double R, double dp, int body, const Vec3& v) {
  const int n = static_cast<int>(std::ceil(R / dp));
  std::size_t count = 0;
  for (int i = -n; i < n; ++i)
    for (int j = -n; j < n; ++j)
      for (int k = -n; k < n; ++k) {
        const Vec3 d((i + 0.5) * dp, (j + 0.5) * dp, (k + 0.5) * dp);
        if (d.squaredNorm() > R * R) continue;
        s.addParticle(c + d, dp * dp * dp, 0, body, v);
        ++count;
      }
  return count;
}

struct Sums {
  Vec3 p0 = Vec3::Zero(), p1 = Vec3::Zero();  // momentum of each body, kg m/s
  double m0 = 0, m1 = 0;                      // mass of each body, kg
};
inline Sums sums(const MpmSolver& s) {
  Sums r;
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (s.body(i) == 0) {
      r.p0 += s.mass(i) * s.velocity(i);
      r.m0 += s.mass(i);
    } else {
      r.p1 += s.mass(i) * s.velocity(i);
      r.m1 += s.mass(i);
    }
  }
  return r;
}

// Rigid-body view of one body's points: mass, centre of mass, its velocity,
// the spin angular momentum about the centre, sum m (x - c) x (v - V), and
// the inertia tensor of the points about the centre, sum m (|r|^2 1 - r r^T);
// spin() = I^-1 L_spin is the angular velocity of the rigid motion that
// carries the same angular momentum.
struct BodyMotion {
  double mass = 0;
  Vec3 centre = Vec3::Zero(), velocity = Vec3::Zero(), spinMomentum = Vec3::Zero();
  Mat3 inertia = Mat3::Zero();
  Vec3 spin() const { return inertia.inverse() * spinMomentum; }
};
inline BodyMotion bodyMotion(const MpmSolver& s, int body) {
  BodyMotion b;
  Vec3 mx = Vec3::Zero(), p = Vec3::Zero();
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (s.body(i) != body) continue;
    b.mass += s.mass(i);
    mx += s.mass(i) * s.position(i);
    p += s.mass(i) * s.velocity(i);
  }
  b.centre = mx / b.mass;
  b.velocity = p / b.mass;
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (s.body(i) != body) continue;
    const Vec3 r = s.position(i) - b.centre;
    b.spinMomentum += s.mass(i) * r.cross(s.velocity(i) - b.velocity);
    b.inertia += s.mass(i) * (r.squaredNorm() * Mat3::Identity() - r * r.transpose());
  }
  return b;
}

}  // namespace needlesim::mpm::test
