#pragma once
// What the mpm engine records besides the forces: markers that follow
// material points (eq 36), the numerical fracture (section 3.4), the particle
// and needle fields for ParaView and the force error against a measured curve (eq 35).
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "needlesim/engines/engine.hpp"
#include "needlesim/engines/mpm/mpm_solver.hpp"
#include "needlesim/io/field_series.hpp"
#include "needlesim/io/table.hpp"
#include "needlesim/scenario/scenario.hpp"

namespace needlesim::engines::mpm_outputs {

using mpm::MpmSolver;
using mpm::Vec3;

// Markers (model.mpm.markers): each follows the material point nearest to its
// position (given from the entry point). markers.csv: ux, uy, uz and the
// in-plane u_xy of eq 36 per marker.
class MarkerSet {
 public:
  MarkerSet(const std::vector<MpmMarkerSpec>& specs, const MpmSolver& solver, const Vec3& entry);
  bool empty() const { return markers_.empty(); }
  void record(const MpmSolver& solver, double t, double depth);
  io::Table& table() { return table_; }
  std::vector<double> largest() const;  // the largest u_xy of each marker so far
  void setLargest(const std::vector<double>& uxy);
  // Final and largest u_xy per marker, and how far the farthest follows its point from its position.
  void results(const MpmSolver& solver, ResultSink& sink) const;
  std::vector<std::string> names() const;

 private:
  struct Marker {
    std::string name;
    std::size_t particle = 0;
    Vec3 x0 = Vec3::Zero();
    double maxUxy = 0.0;
  };
  std::vector<Marker> markers_;
  double farthest_ = 0.0;  // m, largest distance of a marker's point from its given position
  io::Table table_;
};

// Numerical fracture (seed 000 section 3.4): pairs of initially neighbouring
// material points (lattice neighbours, distance <= 1.05 spacing) that end up in
// non-adjacent grid cells or more than 1.5 grid cells apart no longer interact
// through the grid: the tissue has separated between them. Each pair is
// reported once, when it first separates, at the position along the needle
// path of its initial midpoint (docs/models/mpm.md).
struct FractureTracker {
  std::vector<std::uint32_t> a, b;  // neighbouring pairs
  std::vector<std::uint8_t> separated;
  std::vector<double> pathDepth, radial;  // initial midpoint: along the path from the entry point, distance from it
  std::size_t total = 0;
  double onsetDepth = NAN, onsetTime = NAN, deepest = NAN, widest = 0.0;
  io::Table table{{{"time", "s"}, {"tip_depth", "m"}, {"path_depth", "m"}, {"new_pairs", "1"}, {"total_pairs", "1"}}};

  void init(const MpmSolver& s, const Vec3& entry, const Vec3& axis);
  // Marks newly separated pairs; adds one row per grid-cell bin of the path.
  void check(const MpmSolver& s, double t, double tipDepth);
  void results(ResultSink& sink) const;
};

// The particle series for ParaView: displacement and von Mises stress on the reference points (Warp
// By Vector gives the moved particles), in the
// tissue frame (the solver's minus `shift`, MpmSetup::shift), as forces.csv and the other engines,
// and the constant `region` of each point: the index of its layer in tissue.layers, or the number
// of layers plus the index of its inclusion in tissue.inclusions (its solver material).
class ParticleFields {
 public:
  ParticleFields(io::FieldSeries* series, const MpmSolver& solver, const Vec3& shift, const TissueSpec& tissue);
  io::FieldSeries* series() const { return fs_; }
  void write(const MpmSolver& solver, double t);

 private:
  io::FieldSeries* fs_;
  Vec3 shift_;
  std::vector<double> x0_, disp_, vm_;
};

// The needle series for ParaView: the rigid needle's triangulated surface
// (needle/surface_mesh) at each field step, in the tissue frame as the particles.
class NeedleFields {
 public:
  NeedleFields(io::FieldSeries* series, const mpm::RigidBody& needle, const Vec3& shift);
  io::FieldSeries* series() const { return fs_; }
  void write(const mpm::RigidBody& needle, double t);

 private:
  std::vector<double> surfacePoints(const mpm::RigidBody& needle) const;
  io::FieldSeries* fs_;
  Vec3 shift_;
};

// Seed 000 eq 35 against a measured force-depth curve: the simulated force
// interpolated at each measured depth inside the simulated (first, advancing)
// range of depths.
struct ForceError {
  double rmse = 0.0, mae = 0.0;
  std::size_t n = 0;
};
ForceError compareForce(const MeasuredCurve& measured, const std::vector<double>& simDepth,
                        const std::vector<double>& simForce);

}  // namespace needlesim::engines::mpm_outputs
