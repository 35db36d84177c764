#pragma once
// Tetrahedral tissue block of the realtime3d engine: a structured grid, graded laterally
// towards the needle path line (refined there), each hexahedron split into six
// tetrahedra (engines/explicit/mesh.hpp structuredBlock), linear elastic (fe.hpp), with the
// shared real-time dynamics (engines/realtime/tissue_dynamics.hpp: Rayleigh damping, Newmark,
// Prony relaxation, direct / modal / reduced back-ends). The path is the grid line of nodes
// nearest to the needle's reference axis; each path node takes loads along t (axial),
// n (lateral, in the insertion plane) and b (out of plane).
// Coordinates: x = depth from the entry face, y across the width, z across the height, from
// the block's corner (x, y, z >= 0).
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <memory>
#include <vector>

#include "needlesim/engines/realtime/tissue_dynamics.hpp"
#include "needlesim/engines/realtime3d/fe.hpp"

namespace needlesim::realtime3d {

using realtime::Backend;

struct BlockSpec {
  double length = 0.08, width = 0.08, height = 0.08;  // m: x (depth), y, z
  int nodes_depth = 41, nodes_lateral = 16, nodes_height = 16;
  double path_y = 0.04, path_z = 0.04;  // m, the refined line (kept on a grid line)
  double grading = 8.0;                 // ratio coarsest / finest lateral spacing
};

// A sphere of its own material (a bonded inclusion): elements whose centre lies inside
// take it. Mesh coordinates.
struct MaterialRegion {
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();  // m
  double radius = 0.0;                               // m
  ElasticMaterial material;
};

struct TissueConfig : realtime::DynamicsSettings {
  TissueConfig() { modal_max_dofs = 1500; reduced_max_modes = 60; }
  ElasticMaterial material;
  BlockSpec block;
  // Layers by depth band (x of each band's far boundary, ascending); replace `material`.
  std::vector<std::pair<double, ElasticMaterial>> layers;
  std::vector<MaterialRegion> regions;  // over the layers, a later one wins
  // Which faces are held: every face but the entry face x = 0 (seed 003 section 3.5 item 3);
  // hold_sides = false holds the far face x = length only.
  bool hold_sides = true;
  // Plane strain slab (tests against realtime2d): hold the z displacement of every node.
  bool hold_out_of_plane = false;
};

struct PathNode {
  int node = 0;    // mesh node id
  double s = 0.0;  // m, reference position along the axis from the entry point
};

class Tissue {
 public:
  Tissue(const TissueConfig& cfg, const Eigen::Vector3d& entry, const Eigen::Vector3d& axis,
         const Eigen::Vector3d& lateral, double dt);
  const TetMesh& mesh() const { return mesh_; }
  const std::vector<PathNode>& path() const { return path_; }
  const realtime::TissueDynamics& dynamics() const { return *dyn_; }
  realtime::TissueDynamics& dynamics() { return *dyn_; }
  Eigen::Vector3d nodeDisplacement(int node) const;
  Eigen::Vector3d regionDisplacement(std::size_t region) const;
  // The nodes of a material region's elements (indices of the mesh's nodes).
  const std::vector<int>& regionNodes(std::size_t region) const { return region_nodes_.at(region); }
  // Von Mises stress of every element from the current displacement.
  Eigen::VectorXd elementVonMises() const;
  // Boundary faces (triangles, outward node order) of the tet mesh, for viewers.
  const Eigen::Matrix3Xi& surfaceTriangles() const { return surface_; }
  double length() const { return cfg_.block.length; }

 private:
  void assignMaterials();
  realtime::PathedSystem assembleHeld();
  void pickPath(const Eigen::Vector3d& entry);
  TissueConfig cfg_;
  TetMesh mesh_;
  std::vector<double> xs_, ys_, zs_;
  Eigen::Vector3d t_, n_, b_;
  std::vector<PathNode> path_;
  std::vector<bool> held_;  // per DOF
  std::vector<ElasticMaterial> elem_mat_;
  std::vector<std::vector<int>> region_nodes_;
  std::unique_ptr<realtime::TissueDynamics> dyn_;
  Eigen::Matrix3Xi surface_;
};

// Boundary triangles of a tet mesh (faces used by one element), oriented outwards.
Eigen::Matrix3Xi boundaryTriangles(const TetMesh& mesh);

}  // namespace needlesim::realtime3d
