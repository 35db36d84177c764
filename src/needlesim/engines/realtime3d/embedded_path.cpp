// Points embedded along the needle path of realtime3d (embedded_path.hpp).
#include "needlesim/engines/realtime3d/embedded_path.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>

#include "needlesim/core/error.hpp"

namespace needlesim::realtime3d {

namespace {

// The tets that may hold a point of the needle's surface, with their bounding boxes.
class NearAxis {
 public:
  NearAxis(const TetMesh& mesh, const EmbeddingSpec& sp) : mesh_(mesh) {
    for (int e = 0; e < mesh.elements(); ++e) {
      const auto X = tetCorners(mesh, e);
      const Eigen::Vector3d lo = X.rowwise().minCoeff(), hi = X.rowwise().maxCoeff();
      const Eigen::Vector3d c = 0.5 * (lo + hi) - sp.entry;
      const double s = c.dot(sp.t), half = 0.5 * (hi - lo).norm();
      const double off = (c - s * sp.t).norm();
      if (off > sp.radius + half || s < sp.s_begin - sp.spacing - half || s > sp.s_end + sp.spacing + half) continue;
      tets_.push_back(e);
      lo_.push_back(lo);
      hi_.push_back(hi);
    }
  }
  // The tet holding p (the largest smallest shape function, as locateInTets), -1 outside.
  TetPoint locate(const Eigen::Vector3d& p) const {
    TetPoint best;
    double bestMin = -1e-9;
    for (std::size_t k = 0; k < tets_.size(); ++k) {
      const double pad = 1e-9 * (hi_[k] - lo_[k]).norm();
      if (((p - lo_[k]).array() < -pad).any() || ((hi_[k] - p).array() < -pad).any()) continue;
      const Eigen::Vector4d N = tetShapeFunctions(tetCorners(mesh_, tets_[k]), p);
      if (N.minCoeff() > bestMin) {
        bestMin = N.minCoeff();
        best = {tets_[k], N};
      }
    }
    return best;
  }

 private:
  const TetMesh& mesh_;
  std::vector<int> tets_;
  std::vector<Eigen::Vector3d> lo_, hi_;
};

// Edge of the regular tet of element e's volume: its size.
double elementSize(const TetMesh& mesh, int e) {
  Eigen::Matrix<double, 3, 4> dN;
  return std::cbrt(6.0 * std::numbers::sqrt2 * tetGradients(tetCorners(mesh, e), dN));
}

// The interface of a stretch `length` of shaft (embedded_path.hpp): kInterfaceStiffness E per length.
double interfaceCompliance(const ElasticMaterial& m, double length) { return 1.0 / (kInterfaceStiffness * m.E * length); }

// Most quadrature points along the axis and around, each: h/2 apart down to elements of 1/32 of
// a point's stretch of shaft and pi R / 16 (R / 5) around.
constexpr int kMostSamples = 64;

// One point: the quadrature over its patch of the needle's surface (n_s midpoints along the
// axis x n_q around), at most half the local element size apart (sparser points than elements
// would act as point loads, whose displacement grows as 1/h); false when outside the mesh.
bool embedPoint(const TetMesh& mesh, const NearAxis& near, const std::vector<ElasticMaterial>& materials,
                const EmbeddingSpec& sp, double lo, double hi, PathPoint& pt) {
  const TetPoint centre = near.locate(pt.X);
  if (centre.element < 0) return false;
  const double h = elementSize(mesh, centre.element);
  const int ns = std::clamp(static_cast<int>(std::ceil(2.0 * (hi - lo) / h)), 1, kMostSamples);
  const int nq = sp.radius > 0.0 ? std::clamp(static_cast<int>(std::ceil(4.0 * std::numbers::pi * sp.radius / h)), 4, kMostSamples) : 1;
  std::map<int, double> w;
  int found = 0;
  for (int i = 0; i < ns; ++i)
    for (int q = 0; q < nq; ++q) {
      const double s = lo + (hi - lo) * (i + 0.5) / ns, a = 2.0 * std::numbers::pi * (q + 0.5) / nq;
      const Eigen::Vector3d p = sp.entry + s * sp.t + sp.radius * (std::cos(a) * sp.n + std::sin(a) * sp.b);
      const TetPoint at = near.locate(p);
      if (at.element < 0) continue;  // beside an imported surface: the rest carry the load
      ++found;
      for (int c = 0; c < 4; ++c) w[mesh.conn[static_cast<std::size_t>(4 * at.element + c)]] += at.weights[c];
    }
  if (found == 0) return false;
  for (const auto& [node, v] : w)
    if (std::abs(v) > 1e-12 * found) {
      pt.nodes.push_back(node);
      pt.weights.push_back(v / found);
    }
  pt.compliance.setConstant(interfaceCompliance(materials[static_cast<std::size_t>(centre.element)], hi - lo));
  return true;
}

}  // namespace

std::vector<PathPoint> embedPath(const TetMesh& mesh, const std::vector<bool>& held,
                                 const std::vector<ElasticMaterial>& materials, const EmbeddingSpec& sp) {
  if (!(sp.spacing > 0.0)) throw SolverError("realtime3d: the coupling spacing must be > 0");
  const NearAxis near(mesh, sp);
  std::vector<PathPoint> out;
  const int count = static_cast<int>(std::floor((sp.s_end - sp.s_begin) / sp.spacing + 0.5 - 1e-9)) + 1;
  for (int k = 0; k < count; ++k) {  // spacing apart from the entry, each spreading over its stretch of shaft
    PathPoint pt;
    pt.s = sp.s_begin + k * sp.spacing;
    const double lo = std::max(sp.s_begin, pt.s - 0.5 * sp.spacing), hi = std::min(sp.s_end, pt.s + 0.5 * sp.spacing);
    pt.X = sp.entry + pt.s * sp.t;
    if (!(hi > lo) || !embedPoint(mesh, near, materials, sp, lo, hi, pt)) continue;
    double free = 0.0;
    for (std::size_t a = 0; a < pt.nodes.size(); ++a)
      if (!held[static_cast<std::size_t>(3 * pt.nodes[a])]) free += pt.weights[a];
    if (free > 1e-6) out.push_back(std::move(pt));
  }
  if (out.empty()) throw SolverError("realtime3d: no point of the needle path lies in the tissue mesh");
  return out;
}

}  // namespace needlesim::realtime3d
