#include "needlesim/results/inclusion_motion.hpp"

#include "needlesim/core/error.hpp"
#include "needlesim/results/result_sink.hpp"
#include "needlesim/results/target_miss.hpp"

namespace needlesim::results {

namespace {
std::vector<io::Column> columnsFor(const std::vector<InclusionSpec>& inclusions) {
  std::vector<io::Column> c{{"time", "s"}, {"depth", "m"}};
  for (const auto& I : inclusions)
    for (const char* k : {"_ux", "_uy", "_uz", "_u_axial", "_u_lateral", "_u_out_of_plane"})
      c.push_back({I.name + k, "m"});
  return c;
}
}  // namespace

InclusionMotion::InclusionMotion(const std::vector<InclusionSpec>& inclusions, const needle::InsertionFrame& frame)
    : frame_(frame), table_(columnsFor(inclusions)) {
  for (const auto& I : inclusions) {
    names_.push_back(I.name);
    target_.push_back(I.target);
    centre_.emplace_back(I.x, I.y, I.z);
  }
  largest_.assign(names_.size(), 0.0);
  last_.assign(names_.size(), Eigen::Vector3d::Zero());
}

void InclusionMotion::add(double time, double depth, const std::vector<Eigen::Vector3d>& displacement) {
  if (displacement.size() != names_.size())
    throw Error("inclusion motion: " + std::to_string(displacement.size()) + " displacements for " +
                std::to_string(names_.size()) + " inclusions");
  std::vector<double> row{time, depth};
  for (std::size_t i = 0; i < names_.size(); ++i) {
    const Eigen::Vector3d& u = displacement[i];
    row.insert(row.end(), {u.x(), u.y(), u.z(), frame_.axialOf(u), frame_.lateralOf(u), frame_.outOfPlaneOf(u)});
    largest_[i] = std::max(largest_[i], u.norm());
    last_[i] = u;
  }
  table_.addRow(row);
}

void InclusionMotion::tip(const Eigen::Vector3d& position, const Eigen::Vector3d& axis) {
  tipKnown_ = true;
  tip_ = position;
  axis_ = axis.normalized();
}

void InclusionMotion::report(ResultSink& sink) const {
  if (names_.empty()) return;
  sink.table("inclusions", table_);
  for (std::size_t i = 0; i < names_.size(); ++i) {
    const std::string& n = names_[i];
    sink.result(n + "_displacement", last_[i].norm(), "m", "displacement of " + n + " at the end (mean of its material)");
    sink.result(n + "_displacement_max", largest_[i], "m", "largest displacement of " + n + " during the run");
    if (!target_[i]) continue;
    sink.result(n + "_shift_lateral", frame_.lateralOf(last_[i]), "m",
                "shift of " + n + " across the needle path in the insertion plane (targeting error along the frame's lateral)");
    sink.result(n + "_shift_out_of_plane", frame_.outOfPlaneOf(last_[i]), "m",
                "shift of " + n + " out of the insertion plane (targeting error)");
    sink.result(n + "_shift_axial", frame_.axialOf(last_[i]), "m", "shift of " + n + " along the needle axis (pushed ahead of the tip when > 0)");
    if (!tipKnown_) continue;
    const TargetMiss miss = targetMiss(centre_[i], last_[i], tip_, axis_);
    sink.result(n + "_miss_distance", miss.distance, "m", "distance from the needle tip (on its axis) to the displaced centre of " + n + " at the end");
    sink.result(n + "_miss_from_axis", miss.fromAxis, "m",
                "distance of the displaced centre of " + n + " from the needle's axis at the end (how far the needle passes it)");
  }
}

}  // namespace needlesim::results
