#pragma once
// Marker errors of seed 000 eqs 36-37 against markers measured by the user
// (model.mpm.measured_markers, read with the scenario: scenario/measured_data.hpp).
// At each measured depth inside the simulated
// (advancing) depths the simulated displacements are interpolated linearly in
// depth; eq 36 gives u_xy = sqrt(ux^2 + uy^2) and eq 37 the largest and the
// mean |u_xy,exp - u_xy,sim| over the markers, and the same per component
// (the paper's r_max,x, r_max,y, r_mean,x, r_mean,y). docs/models/mpm.md.
#include <string>
#include <vector>

#include "needlesim/scenario/scenario.hpp"

namespace needlesim::mpm {

// Simulated displacement history of one marker, one value per simulated row.
struct MarkerTrack {
  std::string name;
  std::vector<double> ux, uy;  // m
};

// Eq 37 at one measured depth.
struct MarkerErrorRow {
  double depth = 0.0;                     // m
  double rmax = 0.0, rmean = 0.0;         // m, on u_xy (eqs 36-37)
  double rmaxX = 0.0, rmaxY = 0.0;        // m, per component
  double rmeanX = 0.0, rmeanY = 0.0;      // m
  int markers = 0;                        // markers measured at this depth
};

// The advancing part of a simulated run: the rows up to the first maximum
// depth (a repeated depth keeps its last row); their depths go to `depth`.
std::vector<std::size_t> advancingRows(const std::vector<double>& simDepth, std::vector<double>& depth);

// The measured markers are matched to the simulated ones by name.
std::vector<MarkerErrorRow> compareMarkers(const MeasuredMarkers& measured, const std::vector<double>& simDepth,
                                           const std::vector<MarkerTrack>& sim);

}  // namespace needlesim::mpm
