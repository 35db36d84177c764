#include "needlesim/engines/realtime3d/tissue.hpp"

#include <fmt/format.h>
#include <algorithm>
#include <array>
#include <cmath>
#include <map>

#include "needlesim/core/error.hpp"
#include "needlesim/engines/realtime/element_materials.hpp"
#include "needlesim/engines/realtime2d/mesh.hpp"
#include "needlesim/mesh/boundary.hpp"
#include "needlesim/needle/insertion_frame.hpp"

namespace needlesim::realtime3d {

namespace {
void checkBlock(const BlockSpec& b) {
  if (!(b.length > 0.0) || !(b.width > 0.0) || !(b.height > 0.0))
    throw SolverError("realtime3d: the block needs length, width and height > 0");
  if (b.nodes_depth < 3 || b.nodes_lateral < 3 || b.nodes_height < 3)
    throw SolverError("realtime3d: the block needs at least 3 nodes along each direction");
}
}  // namespace

Tissue::Tissue(const TissueConfig& cfg, const Eigen::Vector3d& entry, const Eigen::Vector3d& axis,
               const Eigen::Vector3d& lateral, double dt, double s_begin, double s_end)
    : cfg_(cfg) {
  buildMesh();
  t_ = axis.normalized();
  n_ = (lateral - lateral.dot(t_) * t_).normalized();
  b_ = t_.cross(n_);
  assignMaterials();
  realtime::PathedSystem sys = assembleHeld();
  embed(entry, s_begin, s_end, sys);
  sys.dim = 3;
  sys.dirs.resize(3, 3);
  sys.dirs << t_, n_, b_;
  dyn_ = std::make_unique<realtime::TissueDynamics>("realtime3d", cfg_, sys, dt);
  surface_ = boundaryTriangles(mesh_);
}

// The graded block, or the imported tets moved from the centred tissue frame to the block's corner.
void Tissue::buildMesh() {
  const auto& b = cfg_.block;
  if (const auto& g = cfg_.geometry) {
    if (g->mesh->dim != 3 || g->mesh->element != "tet4")
      throw SolverError("realtime3d: an imported mesh must be 3D of tet4 elements, not " + g->mesh->element);
    mesh_ = explicit_fe::fromImportedGeometry(*g);
    const Eigen::Vector3d shift = needle::cornerShift(b);
    for (std::size_t i = 0; i < mesh_.X.size(); ++i) mesh_.X[i] += shift[static_cast<Eigen::Index>(i % 3)];
    return;
  }
  checkBlock(b);
  std::vector<double> xs;
  for (int i = 0; i < b.nodes_depth; ++i) xs.push_back(b.length * i / (b.nodes_depth - 1));
  // Lateral grading as in realtime2d (finest on the path line, geometric towards the sides).
  const auto ys = realtime2d::gradedCoordinates(b.width, b.path_y, b.nodes_lateral, b.grading);
  const auto zs = realtime2d::gradedCoordinates(b.height, b.path_z, b.nodes_height, b.grading);
  mesh_ = explicit_fe::structuredBlock(xs, ys, zs, explicit_fe::ElementType::Tet4);
}

// Element materials: by the layer of the element centre, then the regions holding it.
void Tissue::assignMaterials() {
  const int ne = mesh_.elements();
  elem_mat_.assign(static_cast<std::size_t>(ne), cfg_.material);
  region_nodes_.assign(cfg_.regions.size(), {});
  std::vector<std::vector<bool>> in(cfg_.regions.size(), std::vector<bool>(static_cast<std::size_t>(mesh_.nodes()), false));
  std::vector<bool> hit;
  const int layers = static_cast<int>(std::max<std::size_t>(1, cfg_.layers.size()));
  for (int e = 0; e < ne; ++e) {
    if (cfg_.geometry) {  // by the element's group: a layer, or an inclusion
      const int r = cfg_.geometry->region.at(static_cast<std::size_t>(e));
      hit.assign(cfg_.regions.size(), false);
      if (r >= layers) hit.at(static_cast<std::size_t>(r - layers)) = true;
      elem_mat_[static_cast<std::size_t>(e)] = r >= layers ? cfg_.regions[static_cast<std::size_t>(r - layers)].material
                                               : cfg_.layers.empty() ? cfg_.material : cfg_.layers[static_cast<std::size_t>(r)].second;
    } else {
      elem_mat_[static_cast<std::size_t>(e)] =
          realtime::materialAt(tetCentre(mesh_, e), cfg_.material, cfg_.layers, cfg_.regions, hit);
    }
    for (std::size_t r = 0; r < hit.size(); ++r)
      for (int a = 0; a < 4 && hit[r]; ++a) in[r][static_cast<std::size_t>(mesh_.conn[static_cast<std::size_t>(4 * e + a)])] = true;
  }
  for (std::size_t r = 0; r < cfg_.regions.size(); ++r)
    for (int n = 0; n < mesh_.nodes(); ++n)
      if (in[r][static_cast<std::size_t>(n)]) region_nodes_[r].push_back(n);
  realtime::requireRegionsMeshed("realtime3d", cfg_.regions, region_nodes_);
}

// K and M with the held faces: the far face, and unless hold_sides is off the four sides.
realtime::PathedSystem Tissue::assembleHeld() {
  const auto a = assemble(mesh_, elem_mat_, cfg_.lumped_mass);
  const int N = mesh_.nodes();
  held_.assign(static_cast<std::size_t>(3 * N), false);
  const double tol = 1e-12;
  const auto& bl = cfg_.block;
  if (const auto& g = cfg_.geometry) {  // the geometry's supported far side, as explicit and mpm hold it
    for (int n = 0; n < N; ++n)
      if (static_cast<std::size_t>(n) < g->supported.size() && g->supported[static_cast<std::size_t>(n)])
        for (int c = 0; c < 3; ++c) held_[static_cast<std::size_t>(3 * n + c)] = true;
    return {a.K, a.M, held_, {}, 3, {}, {}, {}};
  }
  for (int n = 0; n < N; ++n) {
    const double x = mesh_.coord(n, 0), y = mesh_.coord(n, 1), z = mesh_.coord(n, 2);
    const bool side = y < tol || y > bl.width - tol || (!cfg_.hold_out_of_plane && (z < tol || z > bl.height - tol));
    const bool held = x > bl.length - tol || (cfg_.hold_sides && side);
    for (int c = 0; c < 3; ++c)
      if (held || (c == 2 && cfg_.hold_out_of_plane)) held_[static_cast<std::size_t>(3 * n + c)] = true;
  }
  return {a.K, a.M, held_, {}, 3, {}, {}, {}};
}

// Path: points embedded along the reference axis (the axis within 45 deg of the depth direction).
void Tissue::embed(const Eigen::Vector3d& entry, double s_begin, double s_end, realtime::PathedSystem& sys) {
  if (!(t_.x() > std::sqrt(0.5) - 1e-12))
    throw SolverError("realtime3d: the needle axis must be within 45 degrees of the entry-face normal");
  path_ = embedPath(mesh_, held_, elem_mat_, {entry, t_, n_, b_, s_begin, s_end, cfg_.coupling_spacing, cfg_.coupling_radius});
  sys.path_start.push_back(0);
  for (const auto& p : path_) {
    sys.path_nodes.insert(sys.path_nodes.end(), p.nodes.begin(), p.nodes.end());
    sys.path_weights.insert(sys.path_weights.end(), p.weights.begin(), p.weights.end());
    sys.path_start.push_back(static_cast<int>(sys.path_nodes.size()));
  }
}

Eigen::Vector3d Tissue::nodeDisplacement(int node) const {
  return {dyn_->dofDisplacement(3 * node), dyn_->dofDisplacement(3 * node + 1), dyn_->dofDisplacement(3 * node + 2)};
}

Eigen::Vector3d Tissue::pathDisplacement(std::size_t i) const {
  const PathPoint& p = path_.at(i);
  Eigen::Vector3d u = Eigen::Vector3d::Zero();
  for (std::size_t a = 0; a < p.nodes.size(); ++a) u += p.weights[a] * nodeDisplacement(p.nodes[a]);
  return u;
}

bool Tissue::movePathPoint(std::size_t i, const Eigen::Vector3d& X, const Eigen::Vector3d& heading) {
  PathPoint& p = path_.at(i);
  Eigen::Vector3d n = n_ - n_.dot(heading) * heading;
  n.normalize();
  const double half = 0.5 * cfg_.coupling_spacing;
  const EmbeddingSpec sp{X, heading, n, heading.cross(n), -half, half, cfg_.coupling_spacing, cfg_.coupling_radius};
  if (!embedPointAt(mesh_, held_, elem_mat_, sp, p)) return false;
  dyn_->movePathPoint(static_cast<int>(i), p.nodes, p.weights);
  return true;
}

Eigen::Vector3d Tissue::regionDisplacement(std::size_t region) const {
  Eigen::Vector3d u = Eigen::Vector3d::Zero();
  const auto& nodes = region_nodes_.at(region);
  for (int n : nodes) u += nodeDisplacement(n);
  return u / static_cast<double>(nodes.size());
}

Eigen::VectorXd Tissue::elementVonMises() const {
  const auto& u = dyn_->displacement();
  Eigen::VectorXd vm(mesh_.elements());
  for (int e = 0; e < mesh_.elements(); ++e) {
    Eigen::Matrix<double, 12, 1> ue;
    for (int a = 0; a < 4; ++a) ue.segment<3>(3 * a) = u.segment<3>(3 * mesh_.conn[static_cast<std::size_t>(4 * e + a)]);
    vm[e] = vonMises(tetStress(tetCorners(mesh_, e), elasticity(elem_mat_[static_cast<std::size_t>(e)]), ue));
  }
  return vm;
}

Eigen::Matrix3Xi boundaryTriangles(const TetMesh& mesh) {
  // Faces opposite each corner, oriented outwards for a positive tet (a, b, c, d).
  static const int kFaces[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};
  std::map<std::array<int, 3>, std::pair<int, std::array<int, 3>>> seen;
  for (int e = 0; e < mesh.elements(); ++e)
    for (const auto& f : kFaces) {
      std::array<int, 3> tri{};
      for (int q = 0; q < 3; ++q) tri[static_cast<std::size_t>(q)] = mesh.conn[static_cast<std::size_t>(4 * e + f[q])];
      auto key = tri;
      std::sort(key.begin(), key.end());
      auto& entry = seen[key];
      entry.first += 1;
      entry.second = tri;
    }
  std::vector<std::array<int, 3>> out;
  for (const auto& [key, v] : seen)
    if (v.first == 1) out.push_back(v.second);
  Eigen::Matrix3Xi T(3, static_cast<Eigen::Index>(out.size()));
  for (std::size_t i = 0; i < out.size(); ++i) T.col(static_cast<Eigen::Index>(i)) << out[i][0], out[i][1], out[i][2];
  return T;
}

double exitAlongAxis(const ImportedGeometry& g, const Eigen::Vector3d& entry, const Eigen::Vector3d& t) {
  // From beyond the geometry back along the axis: the first crossing is the last exit.
  const Eigen::Vector3d lo(g.lo[0], g.lo[1], g.lo[2]), hi(g.hi[0], g.hi[1], g.hi[2]);
  const double far = (entry - lo).norm() + (entry - hi).norm() + 2.0 * (hi - lo).norm();
  const Eigen::Vector3d from = entry + far * t;
  const auto back = mesh::firstCrossing(*g.mesh, mesh::boundaryFacets(*g.mesh), {from.x(), from.y(), from.z()},
                                        {-t.x(), -t.y(), -t.z()});
  if (!back) throw SolverError("realtime3d: the needle axis does not cross the imported mesh");
  return far - *back;
}

}  // namespace needlesim::realtime3d
