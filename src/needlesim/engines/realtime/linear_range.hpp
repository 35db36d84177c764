#pragma once
// Whether the real-time engines' linear tissue model (seed 003 eqs 3.5-3.11: small strains on the
// reference mesh) still describes the deformed tissue: the small-strain tensor, the rotation of
// the polar decomposition F = R U (F = I + grad u) and the volume ratio J = det F of linear
// simplices (triangles, tetrahedra) from the nodal displacements. An inverted element (J <= 0), a
// strain beyond kLinearStrainBound or a rotation beyond kLinearRotationBound is outside the model;
// LinearRangeWarning says so once (terminal and summary.json warnings).
#include <Eigen/Core>
#include <array>
#include <string>
#include <utility>
#include <vector>

#include "needlesim/engines/engine.hpp"

namespace needlesim::realtime {

// Largest principal small strain (absolute value) the linear model is held to: at 0.2 the
// Green-Lagrange and small strains of a uniaxial stretch already differ by 10 % of the strain.
constexpr double kLinearStrainBound = 0.2;
// Largest element rotation (rad) the linear model is held to. The small strain sym(grad u) of a
// rigid rotation by theta is not zero: its principal values in the rotation plane are
// cos(theta) - 1, a spurious compression of about theta^2 / 2 that the linear model turns into
// stress. Held to the error the strain bound already accepts (Green-Lagrange against small strain
// at the bound: eps^2 / 2 = 0.02), 1 - cos(theta) = 0.02 gives theta = 0.2003 rad (11.5 deg), taken
// as 0.2. docs/models/realtime3d.md "When linear elasticity holds" checks it against the explicit
// engine's finite strains.
constexpr double kLinearRotationBound = 0.2;

struct Deformation {
  double max_strain = 0.0;    // largest |principal small strain| of the elements checked
  double max_rotation = 0.0;  // rad, largest rotation angle of R in F = R U (elements with J > 0)
  int inverted = 0;         // elements with J <= 0
};

class SimplexStrains {
 public:
  SimplexStrains() = default;
  // dim 2 or 3; X: reference coordinates, dim per node; simplices: dim + 1 node ids each.
  SimplexStrains(int dim, const std::vector<double>& X, std::vector<int> simplices);
  // u: displacement, dim per node.
  Deformation measure(const Eigen::VectorXd& u) const;
  bool empty() const { return simplices_.empty(); }

 private:
  int dim_ = 2;
  std::vector<int> simplices_;
  std::vector<double> inverseEdges_;  // dX^-1 of each simplex (edges from its first corner), dim x dim
};

// The rotation angle (rad, in [0, pi]) of R in the polar decomposition F = R U of a 2 x 2 or 3 x 3
// deformation gradient with det F > 0.
double rotationAngle(const Eigen::Matrix2d& F);
double rotationAngle(const Eigen::Matrix3d& F);

// The corner triangles of quadrilaterals (a, b, c, d counter-clockwise; the triangle a, b, c of a
// collapsed quad a, b, c, c): J of each is the quad's J at that corner.
std::vector<int> quadCornerTriangles(const std::vector<std::array<int, 4>>& quads);

class LinearRangeWarning {
 public:
  explicit LinearRangeWarning(std::string engine) : engine_(std::move(engine)) {}
  // Warns the first time d leaves the linear range, at tip depth `depth` (m); returns whether it has warned.
  bool check(const Deformation& d, double depth, ResultSink& sink);
  double worstStrain() const { return worst_; }
  double worstRotation() const { return worstRotation_; }

 private:
  std::string engine_;
  bool warned_ = false;
  double worst_ = 0.0;
  double worstRotation_ = 0.0;
};

// The run's largest strain and rotation in summary.json (max_tissue_strain, max_tissue_rotation) and
// a note naming the bounds; `where` says which elements were checked.
void reportLinearRange(const LinearRangeWarning& range, const std::string& where, ResultSink& sink);

}  // namespace needlesim::realtime
