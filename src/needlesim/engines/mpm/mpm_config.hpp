#pragma once
// The set-up of the MPM solver (grid, shape functions, update scheme, time
// step, faces, bodies), the totals of a step and the particle lattice of a
// box (docs/models/mpm.md).
#include <Eigen/Core>
#include <array>
#include <cstddef>
#include <vector>

namespace needlesim::mpm {

using Vec3 = Eigen::Vector3d;

enum class Shape { Linear, BSpline2 };           // linear hat (the paper's) or quadratic B-spline
enum class Update { USL, MUSL };                 // update-stress-last, modified USL (momentum remap)
enum class FaceBC { Free, Fixed, Roller, NonReflecting };

struct MpmConfig {
  double h = 1e-3;                 // grid spacing, m
  Vec3 origin = Vec3::Zero();      // position of node (0,0,0)
  std::array<int, 3> cells{{10, 10, 10}};
  Shape shape = Shape::BSpline2;
  Update update = Update::MUSL;
  int bodies = 1;                  // deformable velocity fields (1 or 2)
  double flip = 1.0;               // FLIP fraction of the particle velocity update (1 = pure FLIP, eq 4)
  double timeStepFactor = 0.4;     // k_t (eq 26)
  double massScaling = 1.0;        // factor on every particle mass (eq 28 discussion); dt grows with its root
  double fixedTimeStep = 0.0;      // > 0: use this step instead of eq 25-26 (still checked against it)
  double friction = 0.0;           // Coulomb coefficient between deformable bodies
  Vec3 gravity = Vec3::Zero();
  // Box whose faces carry the boundary conditions: faces x-, x+, y-, y+, z-, z+.
  Vec3 boxLo = Vec3::Zero(), boxHi = Vec3::Zero();
  std::array<FaceBC, 6> faces{{FaceBC::Free, FaceBC::Free, FaceBC::Free, FaceBC::Free, FaceBC::Free, FaceBC::Free}};
  // Grid nodes (i, j, k) held fixed besides the faces' (an imported geometry's supported side).
  std::vector<std::array<int, 3>> heldNodes;
  // Two deformable bodies meet in the pair penalty contact (penalty_contact.hpp).
  double penaltyFactor = 0.2;      // kappa, pair stiffness kappa M d_p (M: largest P-wave modulus)
  double penaltyStepFactor = 0.15; // while in contact dt <= this / omega, omega^2 = k / m_r of a pair (0: off)
  int threads = 0;                 // 0 = OpenMP default
  bool fbar = false;               // anti-locking: stress at F-bar with the cell-averaged det F
};

// Totals of one step, for reporting.
struct StepReport {
  double dt = 0.0;
  double kinetic = 0.0;   // J (scaled masses)
  double internal = 0.0;  // J
  double maxSpeed = 0.0;  // max (c_p + |v_p|), m/s
  double contact = 0.0;      // J, energy stored in the penalty contact of two bodies (end-of-step positions)
  double penetration = 0.0;  // m, largest overlap (d_p + d_q)/2 - |x_p - x_q| of two points of different bodies
  double frictionWork = 0.0; // J, work of the penalty contact's friction forces this step (>= 0, dissipated)
};

// Contact force the tissue exerts on one rigid body in the last step.
struct RigidForce {
  Vec3 total = Vec3::Zero(), tip = Vec3::Zero(), shaft = Vec3::Zero();
  int contactNodes = 0;
};

// The particle lattice addBlock fills a box with: n[d] points along each axis, spacing sp[d]
// (dp rounded so that whole points fit), point (i, j, k) at lo + (i + 1/2, j + 1/2, k + 1/2) sp.
struct Lattice {
  Vec3 lo = Vec3::Zero();
  std::array<int, 3> n{{1, 1, 1}};
  Vec3 sp = Vec3::Ones();
  Lattice(const Vec3& lo, const Vec3& hi, double dp);
  std::size_t size() const { return static_cast<std::size_t>(n[0]) * n[1] * n[2]; }
  std::size_t index(int i, int j, int k) const { return (static_cast<std::size_t>(i) * n[1] + j) * n[2] + k; }
  Vec3 point(int i, int j, int k) const { return lo + Vec3((i + 0.5) * sp[0], (j + 0.5) * sp[1], (k + 0.5) * sp[2]); }
};

}  // namespace needlesim::mpm
