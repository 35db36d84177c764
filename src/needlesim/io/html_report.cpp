#include "needlesim/io/html_report.hpp"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>

#include "needlesim/core/embedded.hpp"
#include "needlesim/core/expat_notice.hpp"
#include "needlesim/core/version.hpp"
#include "needlesim/io/references.hpp"

namespace needlesim::io {
namespace {

std::string escape(const std::string& s) {
  std::string o;
  for (char c : s) {
    switch (c) {
      case '<': o += "&lt;"; break;
      case '>': o += "&gt;"; break;
      case '&': o += "&amp;"; break;
      case '"': o += "&quot;"; break;
      default: o += c;
    }
  }
  return o;
}

// Keeps at most kMaxPlotPoints per series: uniform thinning that keeps, in
// each bucket, the minimum and maximum so peaks (puncture) survive.
std::vector<std::pair<double, double>> thin(const PlotSeries& s) {
  std::vector<std::pair<double, double>> pts;
  std::size_t n = std::min(s.x.size(), s.y.size());
  auto ok = [](double v) { return std::isfinite(v); };
  if (n <= kMaxPlotPoints) {
    for (std::size_t i = 0; i < n; ++i)
      if (ok(s.x[i]) && ok(s.y[i])) pts.emplace_back(s.x[i], s.y[i]);
    return pts;
  }
  std::size_t buckets = kMaxPlotPoints / 2;
  for (std::size_t b = 0; b < buckets; ++b) {
    std::size_t i0 = b * n / buckets, i1 = (b + 1) * n / buckets;
    std::size_t imin = i0, imax = i0;
    for (std::size_t i = i0; i < i1; ++i) {
      if (s.y[i] < s.y[imin]) imin = i;
      if (s.y[i] > s.y[imax]) imax = i;
    }
    for (std::size_t i : {std::min(imin, imax), std::max(imin, imax)})
      if (ok(s.x[i]) && ok(s.y[i])) pts.emplace_back(s.x[i], s.y[i]);
  }
  return pts;
}

const char* kPalette[] = {"#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd",
                          "#8c564b", "#e377c2", "#7f7f7f", "#bcbd22", "#17becf"};

// Every text of the report a reader sees, to find the seeds it cites.
std::string visibleText(const HtmlReport& r) {
  std::string t = r.title + "\n" + r.subtitle + "\n";
  for (const auto& [k, v] : r.facts) t += k + " " + v + "\n";
  for (const auto& w : r.warnings) t += w + "\n";
  for (const auto& n : r.notes) t += n + "\n";
  for (const auto& p : r.plots) t += p.title + " " + p.xlabel + " " + p.ylabel + "\n";
  return t;
}

// The full citations of the seeds the report names (docs/references.md).
std::string referencesHtml(const HtmlReport& r) {
  std::string items;
  for (const auto& seed : citedSeeds(visibleText(r))) {
    const auto it = seedCitations().find(seed);
    if (it != seedCitations().end()) items += "<li>seed " + seed + ": " + escape(it->second) + "</li>\n";
  }
  return items.empty() ? std::string() : "<h2>References</h2>\n<ul class=\"references\">\n" + items + "</ul>\n";
}

std::string tableHtml(const HtmlTable& t) {
  std::string h = "<div class=\"tablewrap\"><table class=\"cases\">\n";
  if (!t.caption.empty()) h += "<caption>" + escape(t.caption) + "</caption>\n";
  h += "<thead>";
  if (!t.groups.empty()) {
    h += "<tr class=\"groups\">";
    for (std::size_t g = 0; g < t.groups.size(); ++g)
      h += fmt::format("<th colspan=\"{}\"{}>{}</th>", t.groups[g].second,
                       t.groups[g].first.empty() ? "" : fmt::format(" class=\"g{}\"", g % 2),
                       escape(t.groups[g].first));
    h += "</tr>\n";
  }
  h += "<tr>";
  for (const auto& c : t.header) h += "<th>" + escape(c) + "</th>";
  h += "</tr></thead>\n<tbody>\n";
  for (const auto& row : t.rows) {
    h += "<tr>";
    for (const auto& c : row) h += "<td>" + escape(c) + "</td>";
    h += "</tr>\n";
  }
  return h + "</tbody></table></div>\n";
}

// The y range the plot's series span, for vertical marker lines: (0, 1) without data.
std::pair<double, double> yRange(const Plot& p) {
  double lo = INFINITY, hi = -INFINITY;
  for (const auto& s : p.series)
    for (double y : s.y)
      if (std::isfinite(y)) {
        lo = std::min(lo, y);
        hi = std::max(hi, y);
      }
  if (!(lo <= hi)) return {0.0, 1.0};
  return {lo, hi};
}

// A marker as a grey dashed vertical line over the data's y range; its label is drawn at
// the top end (markerLabel in the page's script) and listed in the legend.
nlohmann::json markerDataset(const PlotMarker& m, std::pair<double, double> y) {
  return {{"label", m.label},
          {"data", {{{"x", m.x}, {"y", y.first}}, {{"x", m.x}, {"y", y.second}}}},
          {"borderColor", "#555555"},
          {"backgroundColor", "#555555"},
          {"showLine", true},
          {"pointRadius", 0},
          {"borderWidth", 1},
          {"borderDash", {3, 3}},
          {"marker", true}};
}

// A series as a Chart.js dataset, coloured by its index `k` in the plot.
nlohmann::json seriesDataset(const PlotSeries& s, std::size_t k) {
  nlohmann::json data = nlohmann::json::array();
  for (auto [x, y] : thin(s)) data.push_back({{"x", x}, {"y", y}});
  const char* color = kPalette[k % 10];
  nlohmann::json ds = {{"label", s.label},     {"data", data},          {"borderColor", color},
                       {"backgroundColor", color}, {"showLine", !s.markers}, {"pointRadius", s.markers ? 2.5 : 0},
                       {"borderWidth", 1.5}};
  if (s.dashed) ds["borderDash"] = {6, 4};
  return ds;
}

// The plots as the page's script reads them (`const plots`).
nlohmann::json plotsJson(const std::vector<Plot>& plots) {
  nlohmann::json out = nlohmann::json::array();
  for (const auto& p : plots) {
    nlohmann::json datasets = nlohmann::json::array();
    std::size_t k = 0;
    for (const auto& s : p.series) datasets.push_back(seriesDataset(s, k++));
    for (const auto& m : p.xmarkers)
      if (std::isfinite(m.x)) datasets.push_back(markerDataset(m, yRange(p)));
    out.push_back({{"title", p.title},
                   {"xlabel", p.xlabel},
                   {"ylabel", p.ylabel},
                   {"logx", p.logx},
                   {"logy", p.logy},
                   {"datasets", datasets}});
  }
  return out;
}

std::string warningsHtml(const std::vector<std::string>& warnings) {
  if (warnings.empty()) return {};
  std::string h = "<div class=\"warnings\" role=\"alert\"><strong>Warnings</strong><ul>\n";
  for (const auto& w : warnings) h += "<li>" + escape(w) + "</li>\n";
  return h + "</ul></div>\n";
}

// The page up to the opening body tag: title, style sheet and Chart.js.
std::string headHtml(const std::string& title) {
  std::string html;
  html += "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\n";
  html += "<title>" + escape(title) + "</title>\n<style>\n"
          "body{font-family:system-ui,sans-serif;margin:2em auto;max-width:1100px;color:#222}\n"
          "h1{font-size:1.5em}table{border-collapse:collapse;margin:1em 0}\n"
          "th,td{border:1px solid #ccc;padding:4px 10px;text-align:left}th{background:#f4f4f4}\n"
          ".plot{position:relative;height:420px;margin:1.5em 0}footer{color:#777;font-size:.8em;margin-top:3em}\n"
          // A wide table scrolls inside its box, which may use the page's right margin and is at
          // most 80 % of the window high, so that its scroll bar is on screen; the header stays.
          ".tablewrap{overflow:auto;width:fit-content;max-height:80vh;"
          "max-width:min(calc(50vw + 550px - 2em),calc(100vw - 2em))}\n"
          ".tablewrap table{margin:0}.tablewrap thead{position:sticky;top:0;z-index:1}"
          ".scrollhint{color:#555;font-size:.9em;margin:.2em 0}\n"
          "table.cases td{text-align:right}tr.groups th{text-align:center}"
          "tr.groups th.g1{background:#dde8f5}tr.groups th.g0{background:#e6f2dc}"
          "caption{text-align:left;font-weight:bold;padding:.3em 0}\n"
          ".warnings{background:#fff3cd;border:2px solid #e0a800;border-radius:4px;padding:.5em 1em;margin:1em 0}\n"
          "</style>\n";
  html += "<script>" + expatNotice("Chart.js (https://www.chartjs.org), from Debian's libjs-chart.js.",
                                    "2014-2021 Chart.js Contributors");
  html += embedded::kChartJs;
  html += "\n</script>\n</head><body>\n";
  return html;
}

// Draws every plot of `const plots` with Chart.js.
const char* const kPlotScript = R"JS(// A marker line's name as a point style drawn beside the line's top end.
function markerLabel(text) {
  const c = document.createElement('canvas'), g = c.getContext('2d');
  g.font = '12px system-ui, sans-serif';
  const w = Math.ceil(g.measureText(text).width) + 6;
  c.width = 2 * w + 4; c.height = 16;
  g.font = '12px system-ui, sans-serif'; g.fillStyle = '#333'; g.textBaseline = 'top';
  g.fillText(text, w + 6, 2);
  return c;
}
plots.forEach(p => p.datasets.filter(d => d.marker).forEach(d => {
  d.pointStyle = ['line', markerLabel(d.label)];
  d.pointRadius = [0, 8];
}));
// A table wider than its box says so above it: its right part is reached by scrolling.
document.querySelectorAll('.tablewrap').forEach(w => {
  if (w.scrollWidth <= w.clientWidth + 1) return;
  const columns = w.querySelectorAll('thead tr:last-child th').length;
  w.insertAdjacentHTML('beforebegin', '<p class="scrollhint">The table is wider than the window: scroll it ' +
    'sideways (scroll bar below it, or shift + mouse wheel) to see all ' + columns + ' columns.</p>');
});
plots.forEach((p, i) => {
  new Chart(document.getElementById('plot' + i), {
    type: 'scatter',
    data: {datasets: p.datasets},
    options: {
      responsive: true, maintainAspectRatio: false, animation: false,
      plugins: {title: {display: true, text: p.title}, legend: {position: 'bottom'}},
      scales: {
        x: {type: p.logx ? 'logarithmic' : 'linear', title: {display: true, text: p.xlabel}},
        y: {type: p.logy ? 'logarithmic' : 'linear', title: {display: true, text: p.ylabel}}
      }
    }
  });
});
</script>
</body></html>
)JS";


}  // namespace

std::string HtmlReport::render() const {
  std::string facts_html;
  for (const auto& [k, v] : facts)
    facts_html += fmt::format("<tr><th>{}</th><td>{}</td></tr>\n", escape(k), escape(v));
  std::string html = headHtml(title);
  html += "<h1>" + escape(title) + "</h1>\n";
  if (!subtitle.empty()) html += "<p>" + escape(subtitle) + "</p>\n";
  html += warningsHtml(warnings);
  if (!facts.empty()) html += "<table>\n" + facts_html + "</table>\n";
  for (const auto& n : notes) html += "<p>" + escape(n) + "</p>\n";
  for (const auto& t : tables) html += tableHtml(t);
  for (std::size_t i = 0; i < plots.size(); ++i)
    html += fmt::format("<div class=\"plot\"><canvas id=\"plot{}\"></canvas></div>\n", i);
  html += referencesHtml(*this);
  html += fmt::format("<footer>needlesim {} ({}); plots drawn with Chart.js (MIT licence).</footer>\n", kVersion,
                      kGitRevision);
  html += "<script>\nconst plots = " + plotsJson(plots).dump() + ";\n";
  html += kPlotScript;
  return html;
}

}  // namespace needlesim::io
