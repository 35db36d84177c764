#pragma once
// forces.csv: the one force table of every engine that moves a needle
// (docs/results.md). Common columns first, in SI, in the shared insertion frame
// (needle/insertion_frame.hpp); an engine's own columns follow, by name.
//   time [s], depth [m]      tip depth along the needle axis from the entry point
//   velocity [m/s]           axial speed of the needle base
//   force_total [N]          axial force on the needle base: minus the tissue's force on
//                            the needle along the axis (> 0 while inserting)
//   force_lateral [N]        the tissue's force on the needle along the frame's lateral
//                            direction (a bevel at orientation 0 gives < 0)
//   tip_x, tip_y, tip_z [m]  the needle's axis at the tip (of the bent needle where it bends) in
//                            the tissue frame: origin at the centre of the entry face, x depth,
//                            y width, z height (a bevel's sharp point: an engine's sharp_* columns)
//   tip_deflection [m]       the tip's offset from the straight axis along `lateral`
//                            (only where the needle is flexible)
#include <cmath>
#include <initializer_list>
#include <vector>

#include "needlesim/io/table.hpp"

namespace needlesim::results {

struct NeedleForces {
  double time = 0.0;
  double depth = 0.0;
  double velocity = 0.0;
  double force_total = 0.0;
  double force_lateral = 0.0;
  double tip_x = 0.0, tip_y = 0.0, tip_z = 0.0;
  double tip_deflection = NAN;  // written only by a flexible-needle table
};

class ForcesTable {
 public:
  // flexible: the needle bends, so tip_deflection is a column. extra: the engine's own columns.
  explicit ForcesTable(bool flexible, std::vector<io::Column> extra = {});
  static std::vector<io::Column> commonColumns(bool flexible);

  void reserve(std::size_t rows) { table_.reserve(rows); }
  // One row: the common values, then the engine's columns in the order given.
  void add(const NeedleForces& f, std::initializer_list<double> extra = {});
  void add(const NeedleForces& f, const std::vector<double>& extra);

  const io::Table& table() const { return table_; }
  io::Table release() { return std::move(table_); }

 private:
  template <class Values>
  void addRow(const NeedleForces& f, const Values& extra);
  bool flexible_;
  std::size_t extra_;
  std::vector<double> row_;
  io::Table table_;
};

}  // namespace needlesim::results
