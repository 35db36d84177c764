#pragma once
// Radius of curvature of a tip path, fitted as seed 002 section 5.1 does: a
// circle fitted to the 3D tip positions over 50 mm sections and over the whole
// insertion (Table 2). Fit: best plane (PCA), algebraic circle (Kasa), then
// geometric least squares (Gauss-Newton on centre and radius).
#include <limits>
#include <span>
#include <vector>

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

// The points whose cumulative arc length from pts[0] lies in [s0, s1].
std::span<const Eigen::Vector3d> pathSection(std::span<const Eigen::Vector3d> pts, double s0, double s1);

// Largest distance of the points from the chord between the first and the last.
double sagitta(std::span<const Eigen::Vector3d> pts);

// A fitted circle describes the points as one circular arc when its rms distance from them
// is at most this share of their sagitta (an S-curve or a path whose curvature changes
// sign is far above it; a model path of slowly varying curvature far below).
inline constexpr double kOneArcRmsShare = 0.02;
// Whether `fit` (of `pts`) is one circular arc: a finite radius within kOneArcRmsShare.
bool isOneArc(const CircleFit& fit, std::span<const Eigen::Vector3d> pts);

// A piece of a path between two breaks (bevel rotations) and the circle fitted to it.
struct PathPiece {
  double s0 = 0.0, s1 = 0.0;  // m, arc length along the path
  CircleFit fit;
  bool arc = false;       // isOneArc
  bool straight = false;  // collinear points: no radius
};
// The path split at the arc lengths `breaks` (ascending; those outside the path are ignored).
std::vector<PathPiece> pathPieces(std::span<const Eigen::Vector3d> pts, std::span<const double> breaks);

// Seed 002 Table 2 layout: three equal sections of `section` metres and the whole.
struct SectionRadii {
  double rho[3] = {0, 0, 0};  // m, per section
  double mean = 0.0;          // m, mean of the three (rho bar)
  double whole = 0.0;         // m, fitted over the whole path (rho exp)
};
SectionRadii sectionRadii(std::span<const Eigen::Vector3d> pts, double section = 0.05);

}  // namespace needlesim::steering
