#pragma once
// Results as a person reads them: the terminal lines of `needlesim run`, the key-results
// table and the plot axes of report.html, the values of a study report. Each value is
// shown in the scenario's display unit of its dimension (Scenario::output.units,
// units::shown); summary.json and the CSV files keep SI (docs/results.md).
#include <string>
#include <string_view>

#include "needlesim/core/units.hpp"
#include "needlesim/io/html_report.hpp"

namespace needlesim::results {

// "2.5 mm" for (0.0025, "m") with lengths in mm; "n/a" for NaN, "none" for an infinite value
// (a crack tip before any crack); a dimensionless result ("1") has no unit. `format` is the
// number's fmt format; `largest` as for units::shown (the unit and round-off of a column).
std::string shownText(double value, std::string_view si_unit, const units::DisplayUnits& display,
                      std::string_view format = "{:.6g}", double largest = -1.0);

// The unit in brackets at the end of an axis label ("tip depth [mm]" -> "mm"); empty if none.
std::string axisUnit(const std::string& label);

// The plot with each axis whose label names a unit of a display dimension ("depth [mm]",
// "force [N]") converted to the display unit for the axis' largest value (units::shown):
// values, markers and label; round-off below 1e-9 of the axis' largest value is 0.
io::Plot inDisplayUnits(io::Plot plot, const units::DisplayUnits& display);

}  // namespace needlesim::results
