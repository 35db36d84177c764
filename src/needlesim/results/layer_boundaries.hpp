#pragma once
// The tissue's layer boundaries on a plot against tip depth: one vertical marker per
// interface, at the depth along the needle where the tip crosses it (the layers' summed
// thicknesses over sin(entry angle), as the lumped model places them), named by the two layers.
#include "needlesim/io/html_report.hpp"
#include "needlesim/scenario/scenario.hpp"

namespace needlesim::results {

// Adds the markers to `plot`, whose x axis is the tip depth in the unit its label names
// ("tip depth [mm]"), less `axis_origin` (m; the depth at x = 0 of a plot against the needle's
// displacement). Nothing for a tissue of one layer.
void markLayerBoundaries(io::Plot& plot, const Scenario& scenario, double axis_origin = 0.0);

}  // namespace needlesim::results
