// Seed 000 eqs 36-37 against measured markers (see marker_errors.hpp).
#include "needlesim/engines/mpm/marker_errors.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>

#include "needlesim/core/error.hpp"

namespace needlesim::mpm {

namespace {

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

// Linear interpolation of y at x on the advancing rows (depth increasing).
double interpolate(const std::vector<double>& d, const std::vector<double>& y, double x) {
  const auto it = std::upper_bound(d.begin(), d.end(), x);
  const std::size_t j = std::clamp<std::size_t>(static_cast<std::size_t>(it - d.begin()), 1, d.size() - 1);
  const double t = d[j] > d[j - 1] ? (x - d[j - 1]) / (d[j] - d[j - 1]) : 1.0;
  return y[j - 1] + t * (y[j] - y[j - 1]);
}

}  // namespace

std::vector<MarkerErrorRow> compareMarkers(const io::CsvData& measured, const std::vector<double>& simDepth,
                                           const std::vector<MarkerTrack>& sim) {
  const int cd = measured.require({"depth", "displacement", "insertion depth"}, units::dim::Length,
                                  "the insertion depth");
  // Column pairs of the simulated markers that the file measures.
  struct Pair { std::size_t track; int cx, cy; };
  std::vector<Pair> pairs;
  std::string names;
  for (std::size_t k = 0; k < sim.size(); ++k) {
    const std::string n = lower(sim[k].name);
    if (!names.empty()) names.append(", ");
    names.append("'").append(n).append("_ux', '").append(n).append("_uy'");
    const int cx = measured.find({n + "_ux"}), cy = measured.find({n + "_uy"});
    if (cx < 0 && cy < 0) continue;
    if (cx < 0 || cy < 0)
      throw InputError({measured.file, measured.headerLine, 0}, "header", n + (cx < 0 ? "_uy" : "_ux"),
                       "marker '" + sim[k].name + "' needs both displacement columns",
                       "'" + n + "_ux [mm]' and '" + n + "_uy [mm]'");
    measured.checkDim(cx, units::dim::Length, "the x displacement of marker " + sim[k].name);
    measured.checkDim(cy, units::dim::Length, "the y displacement of marker " + sim[k].name);
    pairs.push_back({k, cx, cy});
  }
  if (pairs.empty())
    throw InputError({measured.file, measured.headerLine, 0}, "header", "", "no column of any simulated marker",
                     "column pairs " + (names.empty() ? std::string("(the scenario has no markers)") : names));

  // The advancing part of the simulation: rows up to the first maximum depth
  // (a repeated depth keeps its last row).
  std::vector<double> d;
  std::vector<std::size_t> rows;
  for (std::size_t i = 0; i < simDepth.size(); ++i) {
    if (!d.empty() && simDepth[i] < d.back()) break;
    if (!d.empty() && simDepth[i] == d.back()) {
      rows.back() = i;
      continue;
    }
    d.push_back(simDepth[i]);
    rows.push_back(i);
  }
  std::vector<MarkerErrorRow> out;
  if (d.size() < 2) return out;
  std::vector<std::vector<double>> ux(sim.size()), uy(sim.size());
  for (const Pair& p : pairs)
    for (std::size_t r : rows) {
      ux[p.track].push_back(sim[p.track].ux[r]);
      uy[p.track].push_back(sim[p.track].uy[r]);
    }
  const auto& mdepth = measured.col(cd);
  for (std::size_t i = 0; i < measured.rows(); ++i) {
    const double x = mdepth[i];
    if (x < d.front() || x > d.back()) continue;
    MarkerErrorRow e;
    e.depth = x;
    for (const Pair& p : pairs) {
      const double sx = interpolate(d, ux[p.track], x), sy = interpolate(d, uy[p.track], x);
      const double mx = measured.col(p.cx)[i], my = measured.col(p.cy)[i];
      const double exy = std::abs(std::hypot(mx, my) - std::hypot(sx, sy));  // eqs 36-37
      const double ex = std::abs(mx - sx), ey = std::abs(my - sy);
      e.rmax = std::max(e.rmax, exy);
      e.rmaxX = std::max(e.rmaxX, ex);
      e.rmaxY = std::max(e.rmaxY, ey);
      e.rmean += exy;
      e.rmeanX += ex;
      e.rmeanY += ey;
      ++e.markers;
    }
    e.rmean /= e.markers;
    e.rmeanX /= e.markers;
    e.rmeanY /= e.markers;
    out.push_back(e);
  }
  return out;
}

}  // namespace needlesim::mpm
