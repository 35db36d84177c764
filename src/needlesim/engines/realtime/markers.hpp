#pragma once
// Tissue markers of the real-time engines (realtime2d, realtime3d; also the explicit engine): points of the tissue
// followed through a run, like the glitter of seed 003 sections 4.1 and 5.4-5.6. Each engine
// locates a marker in its own element (bilinear quad, linear tet) as up to four nodes and
// their shape-function weights; this class interpolates the displacement u = sum N_a u_a
// (seed 003 eq 3.5), tracks the signed extremes, and writes markers.csv, the key results
// marker_<name>_u{x,y[,z]}_{max,final} and the marker plots.
#include <Eigen/Core>
#include <array>
#include <functional>
#include <string>
#include <vector>

#include "needlesim/engines/engine.hpp"
#include "needlesim/io/table.hpp"

namespace needlesim::engines {

// A marker located in its element: the element's nodes and the shape functions at the point
// (up to eight: the explicit engine's hex8 shares this output).
struct MarkerPoint {
  std::string name;
  std::array<int, 8> nodes{};
  std::array<double, 8> weights{};  // sum 1; unused corners weigh 0
};

class RealtimeMarkers {
 public:
  using NodeDisplacement = std::function<Eigen::Vector3d(int node)>;  // z = 0 in 2D
  // dim: 2 (columns ux, uy) or 3 (ux, uy, uz).
  RealtimeMarkers(int dim, NodeDisplacement nodeDisplacement);

  void add(MarkerPoint marker);
  bool empty() const { return markers_.empty(); }
  std::size_t size() const { return markers_.size(); }
  // Displacement of marker i now: the shape-function interpolation of its nodes (eq 3.5).
  Eigen::Vector3d displacement(std::size_t i) const;
  // Keeps, per component, the signed value of largest magnitude so far.
  void trackExtremes();
  // One row of markers.csv at time t.
  void addRow(double t);
  // marker_<name>_u{x,y[,z]}_max and _final.
  void reportResults(ResultSink& sink) const;
  // Marker paths (x against y) and displacement against time.
  void plot(ResultSink& sink) const;
  // markers.csv into the sink (nothing without markers).
  void writeTable(ResultSink& sink);

 private:
  struct Tracked {
    MarkerPoint point;
    Eigen::Vector3d extreme = Eigen::Vector3d::Zero();
  };
  int dim_;
  NodeDisplacement nodeU_;
  std::vector<Tracked> markers_;
  io::Table table_;
};

}  // namespace needlesim::engines
