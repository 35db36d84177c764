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
};

}  // namespace needlesim::results
