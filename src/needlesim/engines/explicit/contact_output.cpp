#include "needlesim/engines/explicit/contact_output.hpp"

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <map>

#include "needlesim/engines/explicit/solver.hpp"

namespace needlesim::explicit_fe {

namespace {
// local faces of each element type (outward orientation is not needed: areas only)
const std::vector<std::vector<int>>& localFaces(ElementType t) {
  static const std::vector<std::vector<int>> quad = {{0, 1}, {1, 2}, {2, 3}, {3, 0}};
  static const std::vector<std::vector<int>> tri = {{0, 1}, {1, 2}, {2, 0}};
  static const std::vector<std::vector<int>> hex = {{0, 1, 2, 3}, {4, 5, 6, 7}, {0, 1, 5, 4},
                                                    {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}};
  static const std::vector<std::vector<int>> tet = {{0, 1, 2}, {0, 1, 3}, {1, 2, 3}, {0, 2, 3}};
  switch (t) {
    case ElementType::Quad4: return quad;
    case ElementType::Tri3: return tri;
    case ElementType::Hex8: return hex;
    case ElementType::Tet4: return tet;
  }
  return quad;
}
}  // namespace

ContactOutput::ContactOutput(const Mesh& mesh) : dim_(mesh.dim) {
  const auto& faces = localFaces(mesh.type);
  facetNodes_ = static_cast<int>(faces.front().size());
  const int npe = nodesPerElement(mesh.type);
  // a facet shared by two elements is interior; count by the sorted node set
  std::map<std::array<int, 4>, std::pair<int, std::array<int, 4>>> count;
  for (int e = 0; e < mesh.elements(); ++e)
    for (const auto& f : faces) {
      std::array<int, 4> nodes{-1, -1, -1, -1}, key;
      for (std::size_t k = 0; k < f.size(); ++k) nodes[k] = mesh.conn[static_cast<std::size_t>(e) * npe + f[k]];
      key = nodes;
      std::sort(key.begin(), key.end());  // the -1 padding of a 2- or 3-node facet sorts first, alike for all
      auto& c = count[key];
      c.first++;
      c.second = nodes;
    }
  for (const auto& [key, c] : count)
    if (c.first == 1)
      for (int k = 0; k < facetNodes_; ++k) facets_.push_back(c.second[k]);
  area_.assign(mesh.nodes(), 0.0);
  pressure_.assign(mesh.nodes(), 0.0);
}

void ContactOutput::update(const ExplicitSolver& s) {
  const Mesh& m = s.mesh();
  const auto& u = s.displacement();
  const int d = dim_;
  auto x = [&](int n) {
    Eigen::Vector3d p = Eigen::Vector3d::Zero();
    for (int i = 0; i < d; ++i) p[i] = m.X[static_cast<std::size_t>(n) * d + i] + u[static_cast<std::size_t>(n) * d + i];
    return p;
  };
  std::fill(area_.begin(), area_.end(), 0.0);
  const std::size_t nf = facets_.size() / facetNodes_;
  for (std::size_t f = 0; f < nf; ++f) {
    const int* fn = &facets_[f * facetNodes_];
    Eigen::Vector3d an;  // area-weighted facet normal (either sense)
    if (facetNodes_ == 2) {
      const Eigen::Vector3d t = x(fn[1]) - x(fn[0]);
      an = Eigen::Vector3d(-t.y(), t.x(), 0.0);
    } else if (facetNodes_ == 3) {
      an = 0.5 * (x(fn[1]) - x(fn[0])).cross(x(fn[2]) - x(fn[0]));
    } else {
      an = 0.5 * (x(fn[2]) - x(fn[0])).cross(x(fn[3]) - x(fn[1]));
    }
    const double a = an.norm();
    if (!(a > 0)) continue;
    // a node's share counts where the facet faces the rigid body (|n_f . n_contact| > cos 60 deg):
    // the sides at a block's edge or a seam's end do not add area
    for (int k = 0; k < facetNodes_; ++k) {
      const Eigen::Vector3d nc = s.nodeContactNormal(fn[k]);
      if (std::abs(an.dot(nc)) > 0.5 * a) area_[fn[k]] += a / facetNodes_;
    }
  }
  contactArea_ = normalForce_ = maxPressure_ = 0.0;
  for (int n = 0; n < m.nodes(); ++n) {
    const double f = s.nodeContactForce(n);
    pressure_[n] = 0.0;
    if (!(f > 0) || !(area_[n] > 0)) continue;
    pressure_[n] = f / area_[n];
    contactArea_ += area_[n];
    normalForce_ += f;
    maxPressure_ = std::max(maxPressure_, pressure_[n]);
  }
}

}  // namespace needlesim::explicit_fe
