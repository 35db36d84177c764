#pragma once
// Contact pressure and contact area of the explicit engine (docs/models/explicit.md,
// "Contact pressure and area"). The nodal normal contact force f_a (the force the last
// step applied, ExplicitSolver::nodeContactForce) over the node's tributary area on the
// body's surface, A_a = sum over the boundary facets around a of |facet| / n_facet (current
// configuration), is the nodal contact pressure p_a = f_a / A_a (a lumped, row-sum
// recovery of the traction). The contact area is sum_{f_a > 0} A_a, the mean pressure
// sum f_a / area. 2D plane strain: facets are edges, areas per metre of thickness.
#include <vector>

#include "needlesim/engines/explicit/mesh.hpp"

namespace needlesim::explicit_fe {

class ExplicitSolver;

class ContactOutput {
 public:
  explicit ContactOutput(const Mesh& mesh);  // finds the boundary facets (faces of one element)
  // Tributary areas at displacement u (empty = reference) and the pressures of `s`.
  void update(const ExplicitSolver& s);

  const std::vector<double>& pressure() const { return pressure_; }    // per node, Pa
  double contactArea() const { return contactArea_; }                  // m^2 (2D: per metre)
  double normalForce() const { return normalForce_; }                  // N (2D: per metre)
  double meanPressure() const { return contactArea_ > 0 ? normalForce_ / contactArea_ : 0.0; }
  double maxPressure() const { return maxPressure_; }
  int boundaryFacets() const { return static_cast<int>(facets_.size() / std::max(facetNodes_, 1)); }

 private:
  int dim_ = 2, facetNodes_ = 2;
  std::vector<int> facets_;  // facetNodes_ per facet
  std::vector<double> area_, pressure_;
  double contactArea_ = 0.0, normalForce_ = 0.0, maxPressure_ = 0.0;
};

}  // namespace needlesim::explicit_fe
