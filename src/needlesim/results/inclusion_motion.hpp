#pragma once
// inclusions.csv and the targeting results (docs/results.md): the displacement of
// each inclusion (tissue.inclusions) as the mean displacement of its material, in
// the tissue frame and along the needle frame (needle/insertion_frame.hpp). For a
// target, the lateral and out-of-plane parts are the targeting error a fixed aim
// point would make.
#include <string>
#include <vector>

#include <Eigen/Core>

#include "needlesim/io/table.hpp"
#include "needlesim/needle/insertion_frame.hpp"
#include "needlesim/scenario/scenario.hpp"

namespace needlesim {
class ResultSink;
}

namespace needlesim::results {

class InclusionMotion {
 public:
  InclusionMotion(const std::vector<InclusionSpec>& inclusions, const needle::InsertionFrame& frame);
  bool empty() const { return names_.empty(); }
  // Mean displacement of each inclusion's material, in the order of tissue.inclusions.
  void add(double time, double depth, const std::vector<Eigen::Vector3d>& displacement);
  // Where the needle tip is (on its axis, tissue frame, m) and the axis direction: with it the
  // report gives each target's miss distance (tip to the displaced centre) and its distance from
  // the needle's axis.
  void tip(const Eigen::Vector3d& position, const Eigen::Vector3d& axis);
  // inclusions.csv, and per inclusion its final and largest displacement (and, for a
  // target, the final lateral and out-of-plane parts).
  void report(ResultSink& sink) const;
  const io::Table& table() const { return table_; }

 private:
  std::vector<std::string> names_;
  std::vector<bool> target_;
  needle::InsertionFrame frame_;
  io::Table table_;
  std::vector<double> largest_;
  std::vector<Eigen::Vector3d> last_;
  std::vector<Eigen::Vector3d> centre_;  // reference centres (InclusionSpec x, y, z)
  bool tipKnown_ = false;
  Eigen::Vector3d tip_ = Eigen::Vector3d::Zero(), axis_ = Eigen::Vector3d::UnitX();
};

}  // namespace needlesim::results
