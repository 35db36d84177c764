#pragma once
// Marker errors of seed 000 eqs 36-37 against markers measured by the user.
// The measured CSV is wide: a depth column ('depth [mm]') and, per marker,
// '<name>_ux' and '<name>_uy' columns with length units (marker names as in
// model.mpm.markers, any case). At each measured depth inside the simulated
// (advancing) depths the simulated displacements are interpolated linearly in
// depth; eq 36 gives u_xy = sqrt(ux^2 + uy^2) and eq 37 the largest and the
// mean |u_xy,exp - u_xy,sim| over the markers, and the same per component
// (the paper's r_max,x, r_max,y, r_mean,x, r_mean,y). docs/models/mpm.md.
#include <string>
#include <vector>

#include "needlesim/io/csv_reader.hpp"

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

// Throws InputError (file, header line, what is allowed) when the CSV has no
// depth column or no column pair of any simulated marker.
std::vector<MarkerErrorRow> compareMarkers(const io::CsvData& measured, const std::vector<double>& simDepth,
                                           const std::vector<MarkerTrack>& sim);

}  // namespace needlesim::mpm
