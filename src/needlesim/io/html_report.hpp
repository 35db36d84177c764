#pragma once
// A self-contained HTML report: one file, no network, plots drawn by Chart.js
// (Debian's libjs-chart.js, MIT licence) compiled into the binary.
#include <string>
#include <utility>
#include <vector>

namespace needlesim::io {

struct PlotSeries {
  std::string label;
  std::vector<double> x, y;
  bool markers = false;  // true: points only (measured data); false: a line
  bool dashed = false;
};

// A vertical line across a plot at x (in the x axis' unit), named on the plot and in the legend.
struct PlotMarker {
  double x = 0.0;
  std::string label;
};

struct Plot {
  std::string title;
  std::string xlabel, ylabel;  // include units, e.g. "depth [mm]"
  std::vector<PlotSeries> series;
  bool logx = false, logy = false;
  std::vector<PlotMarker> xmarkers{};  // e.g. layer boundaries on a force-depth plot
};

// A table of text cells (escaped on output); `groups` is a row above the
// header that names consecutive columns together: (label, how many columns).
struct HtmlTable {
  std::string caption;
  std::vector<std::pair<std::string, std::size_t>> groups;
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;
};

struct HtmlReport {
  std::string title;
  std::string subtitle;
  std::vector<std::pair<std::string, std::string>> facts;  // key results table
  std::vector<Plot> plots;
  std::vector<std::string> warnings;  // shown in a highlighted box at the top (plain text)
  std::vector<std::string> notes;  // paragraphs (plain text, escaped on output)
  std::vector<HtmlTable> tables;   // after the notes, before the plots

  std::string render() const;
};

// Plots carry at most this many points per series; longer series are thinned
// (keeping extremes) so that a report stays small and fast to open.
inline constexpr std::size_t kMaxPlotPoints = 4000;

}  // namespace needlesim::io
