#pragma once
// Whether the real-time engines' linear tissue model (seed 003 eqs 3.5-3.11: small strains on the
// reference mesh) still describes the deformed tissue: the small-strain tensor and the volume
// ratio J = det(I + grad u) of linear simplices (triangles, tetrahedra) from the nodal
// displacements. An inverted element (J <= 0) or a strain beyond kLinearStrainBound is outside
// the model; LinearRangeWarning says so once (terminal and summary.json warnings).
#include <Eigen/Core>
#include <array>
#include <string>
#include <vector>

#include "needlesim/engines/engine.hpp"

namespace needlesim::realtime {

// Largest principal small strain (absolute value) the linear model is held to: at 0.2 the
// Green-Lagrange and small strains of a uniaxial stretch already differ by 10 % of the strain.
constexpr double kLinearStrainBound = 0.2;

struct Deformation {
  double max_strain = 0.0;  // largest |principal small strain| of the elements checked
  int inverted = 0;         // elements with J <= 0
};

class SimplexStrains {
 public:
  SimplexStrains() = default;
  // dim 2 or 3; X: reference coordinates, dim per node; simplices: dim + 1 node ids each.
  SimplexStrains(int dim, std::vector<double> X, std::vector<int> simplices);
  // u: displacement, dim per node.
  Deformation measure(const Eigen::VectorXd& u) const;
  bool empty() const { return simplices_.empty(); }

 private:
  int dim_ = 2;
  std::vector<double> X_;
  std::vector<int> simplices_;
};

// The corner triangles of quadrilaterals (a, b, c, d counter-clockwise; the triangle a, b, c of a
// collapsed quad a, b, c, c): J of each is the quad's J at that corner.
std::vector<int> quadCornerTriangles(const std::vector<std::array<int, 4>>& quads);

class LinearRangeWarning {
 public:
  explicit LinearRangeWarning(std::string engine) : engine_(std::move(engine)) {}
  // Warns the first time d leaves the linear range, at tip depth `depth` (m); returns whether it has warned.
  bool check(const Deformation& d, double depth, ResultSink& sink);
  double worstStrain() const { return worst_; }

 private:
  std::string engine_;
  bool warned_ = false;
  double worst_ = 0.0;
};

}  // namespace needlesim::realtime
