#pragma once
// The needle path of realtime3d as points embedded in the tetrahedra, independent of where
// the mesh's nodes lie: points at a fixed spacing along the reference axis, each spreading its
// load as a uniform traction over its share of the needle's surface (a cylinder of the needle's
// radius, one spacing long) and reading the tissue's displacement back as the same average.
// The surface is sampled by quadrature points finer than the local elements, each
// interpolating by the linear shape functions (barycentric weights, seed 003 eq 3.5) of the tet
// holding it; the point's entries are the nodes of those tets with the summed weights. A
// point's path compliance W^T K^-1 W then has a finite limit under mesh refinement once the
// elements are finer than the needle (a point load's displacement would grow without bound, as
// ln(1/h) along a line). A stiff interface in series with each tie (kInterfaceStiffness E per
// length of shaft) keeps the coupling well posed where several points share one tet and so
// cannot move independently.
#include <Eigen/Core>
#include <vector>

#include "needlesim/engines/realtime3d/fe.hpp"

namespace needlesim::realtime3d {

// Stiffness of the needle-tissue interface per length of shaft, in units of the local Young's
// modulus: 50 E, a few % of the tissue's own compliance at the shaft.
constexpr double kInterfaceStiffness = 50.0;
struct PathPoint {
  double s = 0.0;                     // m, reference position along the axis from the entry point
  Eigen::Vector3d X = Eigen::Vector3d::Zero();  // m, the point on the axis (mesh coordinates)
  std::vector<int> nodes;             // mesh nodes it interpolates
  std::vector<double> weights;        // their weights (sum 1)
  Eigen::Vector3d compliance = Eigen::Vector3d::Zero();  // m/N, the interface in series with its ties (t, n, b)
};

struct EmbeddingSpec {
  Eigen::Vector3d entry = Eigen::Vector3d::Zero();  // m, where s = 0 (mesh coordinates)
  Eigen::Vector3d t = Eigen::Vector3d::UnitX(), n = Eigen::Vector3d::UnitY(), b = Eigen::Vector3d::UnitZ();
  double s_begin = 0.0, s_end = 0.0;  // m, the stretch of the axis inside the tissue
  double spacing = 1e-3;              // m, between points
  double radius = 0.0;                // m, the needle's outer radius (0: points on the axis)
};

// The points from s_begin to s_end, `spacing` apart from s_begin (the first on the entry, tied
// as soon as the tip is in), each spreading over half a spacing either side, cut at s_begin and
// s_end; those whose every node is held (their x DOF) are left out.
// `materials` per element (for the interface). Throws SolverError when none lies in the mesh.
std::vector<PathPoint> embedPath(const TetMesh& mesh, const std::vector<bool>& held,
                                 const std::vector<ElasticMaterial>& materials, const EmbeddingSpec& spec);

// One point embedded at spec.entry (s = 0), spreading over its needle surface from s_begin to
// s_end along spec.t (a channel's heading), into pt (nodes, weights, X, compliance; pt.s kept).
// False when it lies outside the mesh or on held nodes only.
bool embedPointAt(const TetMesh& mesh, const std::vector<bool>& held, const std::vector<ElasticMaterial>& materials,
                  const EmbeddingSpec& spec, PathPoint& pt);

}  // namespace needlesim::realtime3d
