#include "needlesim/engines/realtime2d/tissue.hpp"

#include <Eigen/SparseCholesky>
#include <fmt/format.h>
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "needlesim/core/error.hpp"
#include "needlesim/engines/realtime/element_materials.hpp"
#include "needlesim/engines/realtime2d/imported_mesh.hpp"
#include "needlesim/needle/insertion_frame.hpp"

namespace needlesim::realtime2d {

namespace {
Eigen::Vector2d elementCentre(const Mesh& mesh, int e) {
  Eigen::Vector2d c = Eigen::Vector2d::Zero();
  for (int a = 0; a < 4; ++a) c += 0.25 * mesh.nodes.col(mesh.quads(a, e));
  return c;
}

// Winkler springs on the held sides: k times each node's tributary boundary length times t.
Eigen::SparseMatrix<double> boundarySprings(const Mesh& mesh, double k, double thickness) {
  std::vector<Eigen::Triplet<double>> t;
  auto add = [&](int node, double len) {
    t.emplace_back(2 * node, 2 * node, k * len * thickness);
    t.emplace_back(2 * node + 1, 2 * node + 1, k * len * thickness);
  };
  auto trib = [](const std::vector<double>& c, int i) {
    const int n = static_cast<int>(c.size());
    double l = 0.0;
    if (i > 0) l += 0.5 * (c[static_cast<std::size_t>(i)] - c[static_cast<std::size_t>(i - 1)]);
    if (i + 1 < n) l += 0.5 * (c[static_cast<std::size_t>(i + 1)] - c[static_cast<std::size_t>(i)]);
    return l;
  };
  for (int i = 0; i < mesh.nx; ++i) {
    add(mesh.node(i, 0), trib(mesh.xs, i));
    add(mesh.node(i, mesh.ny - 1), trib(mesh.xs, i));
  }
  for (int j = 0; j < mesh.ny; ++j) add(mesh.node(mesh.nx - 1, j), trib(mesh.ys, j));
  const int N = 2 * mesh.nodeCount();
  Eigen::SparseMatrix<double> Ks(N, N);
  Ks.setFromTriplets(t.begin(), t.end());
  return Ks;
}


// An imported element's material by its region: the (one) layer, or inclusion i.
ElasticMaterial regionMaterial(const TissueConfig& cfg, int region, std::vector<bool>& hit) {
  hit.assign(cfg.regions.size(), false);
  const int layers = static_cast<int>(std::max<std::size_t>(1, cfg.layers.size()));
  if (region < layers) return cfg.material;
  hit.at(static_cast<std::size_t>(region - layers)) = true;
  return cfg.regions[static_cast<std::size_t>(region - layers)].material;
}

Mesh meshOf(const TissueConfig& cfg) {
  if (!cfg.geometry) return generateMesh(cfg.mesh);
  TissueSpec block;
  block.width = cfg.mesh.width;
  return importedMesh(*cfg.geometry, needle::cornerShift(block).head<2>());
}

std::vector<bool> heldNodes(const TissueConfig& cfg, const Mesh& mesh) {
  if (cfg.geometry && cfg.support_stiffness > 0.0)
    throw SolverError("realtime2d: spring supports are not available on an imported mesh");
  return cfg.geometry ? importedHeld(*cfg.geometry) : nodesOnHeldSides(mesh);
}
}  // namespace

// ---------------------------------------------------------------------------
Tissue::Tissue(const TissueConfig& cfg, const Eigen::Vector2d& entry, const Eigen::Vector2d& axis, double dt)
    : mesh_(meshOf(cfg)), cfg_(cfg) {
  t_ = axis.normalized();
  n_ = Eigen::Vector2d(-t_.y(), t_.x());
  assignMaterials(entry);
  const std::vector<bool> onSides = heldNodes(cfg_, mesh_);
  realtime::PathedSystem sys = assembleSupported(onSides);
  pickPath(entry, onSides);
  for (const auto& p : path_) sys.path_nodes.push_back(p.node);
  sys.dirs.resize(2, 2);
  sys.dirs << t_, n_;
  dyn_ = std::make_unique<realtime::TissueDynamics>("realtime2d", cfg_, sys, dt);
}

// Element materials: by the layer of the element centre, then the material regions
// (inclusions) holding the centre, then the stiffening around the needle path.
void Tissue::assignMaterials(const Eigen::Vector2d& entry) {
  const auto& cfg = cfg_;
  elem_mat_.assign(static_cast<std::size_t>(mesh_.elementCount()), cfg.material);
  std::vector<std::vector<bool>> inRegion(cfg.regions.size(), std::vector<bool>(static_cast<std::size_t>(mesh_.nodeCount()), false));
  std::vector<bool> hit;
  for (int e = 0; e < mesh_.elementCount(); ++e) {
    ElasticMaterial& m = elem_mat_[static_cast<std::size_t>(e)];
    m = cfg.geometry ? regionMaterial(cfg, cfg.geometry->region.at(static_cast<std::size_t>(e)), hit)
                     : realtime::materialAt(elementCentre(mesh_, e), cfg.material, cfg.layers, cfg.regions, hit);
    for (std::size_t r = 0; r < cfg.regions.size(); ++r)
      for (int a = 0; a < 4 && hit[r]; ++a) inRegion[r][static_cast<std::size_t>(mesh_.quads(a, e))] = true;
    m.thickness = cfg.material.thickness;
    m.plane_strain = cfg.material.plane_strain;
  }
  region_nodes_.assign(cfg.regions.size(), {});
  for (std::size_t r = 0; r < cfg.regions.size(); ++r)
    for (int n = 0; n < mesh_.nodeCount(); ++n)
      if (inRegion[r][static_cast<std::size_t>(n)]) region_nodes_[r].push_back(n);
  realtime::requireRegionsMeshed("realtime2d", cfg.regions, region_nodes_);
  if (cfg.stiffening_factor != 1.0 && cfg.stiffening_radius > 0.0) {
    if (!(cfg.stiffening_factor > 0.0)) throw SolverError("realtime2d: the stiffening factor must be > 0");
    // Seed 003 section 3.5 item 4: the tissue around the needle path is stiffer (the shaft
    // confines it), so nodes next to the shaft are dragged less and the needle slips past.
    for (int e = 0; e < mesh_.elementCount(); ++e)
      if (std::abs((elementCentre(mesh_, e) - entry).dot(n_)) <= cfg.stiffening_radius)
        elem_mat_[static_cast<std::size_t>(e)].E *= cfg.stiffening_factor;
  }
}

// K and M on the free DOFs: every side but the entry face held (seed 003 section 3.5
// item 3), or Winkler springs there instead.
realtime::PathedSystem Tissue::assembleSupported(const std::vector<bool>& onSides) {
  const auto asm_ = assemble(mesh_, elem_mat_, cfg_.lumped_mass);
  const int N = mesh_.nodeCount();
  held_.assign(static_cast<std::size_t>(2 * N), false);
  realtime::PathedSystem sys;
  sys.K = asm_.K;
  sys.M = asm_.M;
  if (cfg_.support_stiffness > 0.0) {
    sys.K += boundarySprings(mesh_, cfg_.support_stiffness, cfg_.material.thickness);
  } else {
    for (int i = 0; i < N; ++i)
      if (onSides[static_cast<std::size_t>(i)]) held_[static_cast<std::size_t>(2 * i)] = held_[static_cast<std::size_t>(2 * i + 1)] = true;
  }
  sys.held = held_;
  return sys;
}

// Path: per depth column the node nearest to the reference axis line (axis within
// 45 deg of the depth direction), from the entry face on; held nodes excluded.
void Tissue::pickPath(const Eigen::Vector2d& entry, const std::vector<bool>& onSides) {
  if (!mesh_.structured()) {
    path_ = pathNearAxis(mesh_, onSides, entry, t_);
    if (path_.empty()) throw SolverError("realtime2d: no free node of the imported mesh lies on the needle path");
    return;
  }
  if (!(t_.x() > std::sqrt(0.5) - 1e-12))
    throw SolverError("realtime2d: the needle axis must be within 45 degrees of the entry-face normal");
  for (int i = 0; i < mesh_.nx; ++i) {
    const double s = (mesh_.xs[static_cast<std::size_t>(i)] - entry.x()) / t_.x();
    if (s < -1e-12) continue;
    const double y = entry.y() + s * t_.y();
    const auto it = std::min_element(mesh_.ys.begin(), mesh_.ys.end(),
                                     [&](double a, double b) { return std::abs(a - y) < std::abs(b - y); });
    const int j = static_cast<int>(it - mesh_.ys.begin());
    const int node = mesh_.node(i, j);
    if (held_[static_cast<std::size_t>(2 * node)] || (cfg_.support_stiffness <= 0.0 && onSides[static_cast<std::size_t>(node)]))
      continue;
    const Eigen::Vector2d d = mesh_.nodes.col(node) - entry;
    path_.push_back({node, d.dot(t_), d.dot(n_)});
  }
  if (path_.empty()) throw SolverError("realtime2d: no mesh node lies on the needle path");
}

Tissue::~Tissue() = default;
Tissue::Tissue(Tissue&&) noexcept = default;
Tissue& Tissue::operator=(Tissue&&) noexcept = default;

Eigen::Vector2d Tissue::nodeDisplacement(int node) const {
  return {dyn_->dofDisplacement(2 * node), dyn_->dofDisplacement(2 * node + 1)};
}

Eigen::Vector2d Tissue::regionDisplacement(std::size_t region) const {
  Eigen::Vector2d u = Eigen::Vector2d::Zero();
  const auto& nodes = region_nodes_.at(region);
  for (int n : nodes) u += nodeDisplacement(n);
  return u / static_cast<double>(nodes.size());
}

Eigen::Matrix4Xd Tissue::elementStresses() const {
  const auto& u = displacement();
  Eigen::Matrix4Xd s(4, mesh_.elementCount());
  for (int e = 0; e < mesh_.elementCount(); ++e) {
    Eigen::Matrix<double, 2, 4> xy;
    Eigen::Matrix<double, 8, 1> ue;
    for (int a = 0; a < 4; ++a) {
      const int n = mesh_.quads(a, e);
      xy.col(a) = mesh_.nodes.col(n);
      ue.segment<2>(2 * a) = u.segment<2>(2 * n);
    }
    const auto& m = elem_mat_[static_cast<std::size_t>(e)];
    const Eigen::Vector3d sig = quadCentreStress(xy, elasticity(m), ue);
    s.col(e) << sig, m.plane_strain ? m.nu * (sig[0] + sig[1]) : 0.0;
  }
  return s;
}
}  // namespace needlesim::realtime2d
