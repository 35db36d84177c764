#pragma once
// Tetrahedral tissue of the realtime3d engine: a structured grid, graded laterally towards
// the needle path line (refined there), each hexahedron split into six tetrahedra
// (engines/explicit/mesh.hpp structuredBlock), or an imported tet mesh (tissue.geometry,
// its groups the layers and inclusions, held where the geometry is supported); linear elastic
// (fe.hpp), with the shared real-time dynamics (engines/realtime/tissue_dynamics.hpp: Rayleigh
// damping, Newmark, Prony relaxation, direct / modal / reduced back-ends). The path is a row of
// points embedded in the tets along the needle's reference axis (embedded_path.hpp), at a fixed
// spacing whatever the mesh; each takes loads along t (axial), n (lateral, in the insertion
// plane) and b (out of plane).
// Coordinates: x = depth from the entry face, y across the width, z across the height, from
// the block's corner (x, y, z >= 0).
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <memory>
#include <vector>

#include "needlesim/engines/realtime/tissue_dynamics.hpp"
#include "needlesim/engines/realtime3d/embedded_path.hpp"
#include "needlesim/engines/realtime3d/fe.hpp"
#include "needlesim/scenario/scenario.hpp"

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
  // An imported tet mesh (centred tissue frame) instead of the block: element materials by its
  // groups (region < layers: layer, else regions[region - layers]), held where `supported`;
  // the block's extents are its bounding box.
  std::shared_ptr<const ImportedGeometry> geometry;
  double coupling_spacing = 1e-3;  // m, between the path points
  double coupling_radius = 0.0;    // m, the needle's outer radius (the surface the loads spread over)
  // Where the path points lie: on the straight reference axis, or (follow_tip) on the channel
  // the tip cuts, each placed when the tip reaches its depth (session.hpp), the tip turning
  // towards the bevel at `channel_curvature` (1/m) per length inserted.
  bool follow_tip = false;
  double channel_curvature = 0.0;
};

class Tissue {
 public:
  // The path from s_begin to s_end along the axis from `entry` (mesh coordinates).
  Tissue(const TissueConfig& cfg, const Eigen::Vector3d& entry, const Eigen::Vector3d& axis,
         const Eigen::Vector3d& lateral, double dt, double s_begin, double s_end);
  const TetMesh& mesh() const { return mesh_; }
  const std::vector<PathPoint>& path() const { return path_; }
  const realtime::TissueDynamics& dynamics() const { return *dyn_; }
  realtime::TissueDynamics& dynamics() { return *dyn_; }
  Eigen::Vector3d nodeDisplacement(int node) const;
  Eigen::Vector3d regionDisplacement(std::size_t region) const;
  // The nodes of a material region's elements (indices of the mesh's nodes).
  const std::vector<int>& regionNodes(std::size_t region) const { return region_nodes_.at(region); }
  // Displacement of path point i: its nodes' weighted sum (the tissue side of its ties).
  Eigen::Vector3d pathDisplacement(std::size_t i) const;
  // Moves path point i, before it takes any load, to X (mesh coordinates) on a channel heading
  // along unit `heading`: embedded in the tets there (embedPointAt). False (and unmoved) when X
  // lies outside the mesh.
  bool movePathPoint(std::size_t i, const Eigen::Vector3d& X, const Eigen::Vector3d& heading);
  // Von Mises stress of every element from the current displacement.
  Eigen::VectorXd elementVonMises() const;
  // Boundary faces (triangles, outward node order) of the tet mesh, for viewers.
  const Eigen::Matrix3Xi& surfaceTriangles() const { return surface_; }
  double length() const { return cfg_.block.length; }

 private:
  void buildMesh();
  void assignMaterials();
  realtime::PathedSystem assembleHeld();
  void embed(const Eigen::Vector3d& entry, double s_begin, double s_end, realtime::PathedSystem& sys);
  TissueConfig cfg_;
  TetMesh mesh_;
  Eigen::Vector3d t_, n_, b_;
  std::vector<PathPoint> path_;
  std::vector<bool> held_;  // per DOF
  std::vector<ElasticMaterial> elem_mat_;
  std::vector<std::vector<int>> region_nodes_;
  std::unique_ptr<realtime::TissueDynamics> dyn_;
  Eigen::Matrix3Xi surface_;
};

// Boundary triangles of a tet mesh (faces used by one element), oriented outwards.
Eigen::Matrix3Xi boundaryTriangles(const TetMesh& mesh);

// Where the axis from `entry` along unit `t` (centred tissue frame) leaves the imported
// geometry for the last time, along the axis.
double exitAlongAxis(const ImportedGeometry& geometry, const Eigen::Vector3d& entry, const Eigen::Vector3d& t);

}  // namespace needlesim::realtime3d
