#include "needlesim/engines/realtime/markers.hpp"

#include <cmath>

#include "needlesim/engines/realtime/run_report.hpp"

namespace needlesim::engines {

namespace {
constexpr const char* kAxis[3] = {"x", "y", "z"};
constexpr const char* kDirection[3] = {"depth-wise", "lateral", "out-of-plane"};
}  // namespace

RealtimeMarkers::RealtimeMarkers(int dim, NodeDisplacement nodeDisplacement)
    : dim_(dim), nodeU_(std::move(nodeDisplacement)), table_(std::vector<io::Column>{{"time", "s"}}) {}

void RealtimeMarkers::add(MarkerPoint marker) {
  std::vector<io::Column> cols = table_.columns();
  for (int c = 0; c < dim_; ++c) cols.push_back({marker.name + "_u" + kAxis[c], "m"});
  table_ = io::Table(std::move(cols));
  markers_.push_back({std::move(marker), Eigen::Vector3d::Zero()});
}

// u(X) = sum_a N_a(X) u_a over the element's nodes (seed 003 eq 3.5).
Eigen::Vector3d RealtimeMarkers::displacement(std::size_t i) const {
  const MarkerPoint& p = markers_[i].point;
  Eigen::Vector3d u = Eigen::Vector3d::Zero();
  for (std::size_t a = 0; a < p.nodes.size(); ++a)
    if (p.weights[a] != 0.0) u += p.weights[a] * nodeU_(p.nodes[a]);
  return u;
}

void RealtimeMarkers::trackExtremes() {
  for (std::size_t i = 0; i < markers_.size(); ++i) {
    const Eigen::Vector3d u = displacement(i);
    Eigen::Vector3d& e = markers_[i].extreme;
    for (int c = 0; c < 3; ++c)
      if (std::abs(u[c]) > std::abs(e[c])) e[c] = u[c];
  }
}

void RealtimeMarkers::addRow(double t) {
  std::vector<double> row{t};
  for (std::size_t i = 0; i < markers_.size(); ++i) {
    const Eigen::Vector3d u = displacement(i);
    for (int c = 0; c < dim_; ++c) row.push_back(u[c]);
  }
  table_.addRow(row);
}

void RealtimeMarkers::reportResults(ResultSink& sink) const {
  for (std::size_t i = 0; i < markers_.size(); ++i) {
    const std::string& name = markers_[i].point.name;
    const std::string key = "marker_" + name + "_u";
    const Eigen::Vector3d u = displacement(i);
    for (int c = 0; c < dim_; ++c)
      sink.result(key + kAxis[c] + "_max", markers_[i].extreme[c], "m",
                  std::string("largest ") + kDirection[c] + " displacement of marker " + name);
    for (int c = 0; c < dim_; ++c)
      sink.result(key + kAxis[c] + "_final", u[c], "m",
                  std::string("final ") + kDirection[c] + " displacement of marker " + name);
  }
}

void RealtimeMarkers::plot(ResultSink& sink) const {
  if (markers_.empty()) return;
  io::Plot paths{"Marker paths", "x displacement [mm]", "y displacement [mm]", {}};
  io::Plot against{"Marker displacement against time", "time [s]", "displacement [mm]", {}};
  const auto time = table_.column("time");
  for (const auto& m : markers_) {
    const std::string& n = m.point.name;
    const auto ux = realtimeMm(table_.column(n + "_ux")), uy = realtimeMm(table_.column(n + "_uy"));
    paths.series.push_back({n, ux, uy, false, false});
    against.series.push_back({n + " x", time, ux, false, false});
    against.series.push_back({n + " y", time, uy, false, true});
    if (dim_ == 3) against.series.push_back({n + " z", time, realtimeMm(table_.column(n + "_uz")), false, true});
  }
  sink.plot(std::move(paths));
  sink.plot(std::move(against));
}

void RealtimeMarkers::writeTable(ResultSink& sink) {
  if (!markers_.empty()) sink.table("markers", std::move(table_));
}

}  // namespace needlesim::engines
