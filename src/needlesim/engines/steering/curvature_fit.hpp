#pragma once
// Radius of curvature of a tip path, fitted as seed 002 section 5.1 does: a
// circle fitted to the 3D tip positions over 50 mm sections and over the whole
// insertion (Table 2). Fit: best plane (PCA), algebraic circle (Kasa), then
// geometric least squares (Gauss-Newton on centre and radius).
#include <limits>
#include <span>

#include <Eigen/Core>

namespace needlesim::steering {

struct CircleFit {
  double radius = std::numeric_limits<double>::infinity();  // m; inf for a straight path
  double rms = 0.0;         // m, rms distance of the points from the fitted circle
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();  // plane normal
  int points = 0;
};

// Fits a circle to >= 3 points. Radius is inf when the points are collinear
// within `straight_tol` (relative sagitta: sagitta / chord).
CircleFit fitCircle(std::span<const Eigen::Vector3d> pts, double straight_tol = 1e-9);

// Fits over the points whose cumulative arc length from pts[0] lies in [s0, s1].
CircleFit fitCircleSection(std::span<const Eigen::Vector3d> pts, double s0, double s1);

// Seed 002 Table 2 layout: three equal sections of `section` metres and the whole.
struct SectionRadii {
  double rho[3] = {0, 0, 0};  // m, per section
  double mean = 0.0;          // m, mean of the three (rho bar)
  double whole = 0.0;         // m, fitted over the whole path (rho exp)
};
SectionRadii sectionRadii(std::span<const Eigen::Vector3d> pts, double section = 0.05);

}  // namespace needlesim::steering
