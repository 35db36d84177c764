#pragma once
// The measured data an mpm scenario compares with (model.mpm.measured_force,
// model.mpm.measured_markers), read from their CSV files when the scenario is
// read, so that `needlesim check` refuses a bad file and the engine reads none.
#include <vector>

#include "needlesim/io/csv_reader.hpp"
#include "needlesim/scenario/scenario.hpp"

namespace needlesim::scenario {

// Fills m.measured_force and m.measured_markers from the files their paths
// name (nothing for an empty path). InputError naming the file and the line or
// column: an empty file, no depth or force column, a unit of another dimension,
// a marker with only one of its columns, or no column of any marker.
void loadMeasuredData(MpmModelSpec& m);

// The measured curve in csv: a depth and a force column (any length and force units).
MeasuredCurve measuredCurveFrom(const io::CsvData& csv);
// The tracks in csv (wide: a depth column, '<name>_ux' and '<name>_uy' per
// marker, names of `markers` matched in any case).
MeasuredMarkers measuredMarkersFrom(const io::CsvData& csv, const std::vector<MpmMarkerSpec>& markers);

}  // namespace needlesim::scenario
