// Seed 000 eqs 36-37 against measured markers (see marker_errors.hpp).
#include "needlesim/engines/mpm/marker_errors.hpp"

#include <algorithm>
#include <cmath>

namespace needlesim::mpm {

namespace {

// Linear interpolation of y at x on the advancing rows (depth increasing).
double interpolate(const std::vector<double>& d, const std::vector<double>& y, double x) {
  const auto it = std::upper_bound(d.begin(), d.end(), x);
  const std::size_t j = std::clamp<std::size_t>(static_cast<std::size_t>(it - d.begin()), 1, d.size() - 1);
  const double t = d[j] > d[j - 1] ? (x - d[j - 1]) / (d[j] - d[j - 1]) : 1.0;
  return y[j - 1] + t * (y[j] - y[j - 1]);
}

// A measured track and the simulated one on the advancing rows.
struct Pair {
  const MeasuredMarkers::Track* measured;
  std::vector<double> ux, uy;
};

// Eq 37 at measured row i (depth x).
MarkerErrorRow errorsAt(const std::vector<Pair>& pairs, const std::vector<double>& d, std::size_t i, double x) {
  MarkerErrorRow e;
  e.depth = x;
  for (const Pair& p : pairs) {
    const double sx = interpolate(d, p.ux, x), sy = interpolate(d, p.uy, x);
    const double mx = p.measured->ux[i], my = p.measured->uy[i];
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
  return e;
}

}  // namespace

std::vector<std::size_t> advancingRows(const std::vector<double>& simDepth, std::vector<double>& d) {
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
  return rows;
}

std::vector<MarkerErrorRow> compareMarkers(const MeasuredMarkers& measured, const std::vector<double>& simDepth,
                                           const std::vector<MarkerTrack>& sim) {
  std::vector<double> d;
  const std::vector<std::size_t> rows = advancingRows(simDepth, d);
  std::vector<MarkerErrorRow> out;
  if (d.size() < 2) return out;
  std::vector<Pair> pairs;
  for (const auto& m : measured.markers)
    for (const MarkerTrack& s : sim) {
      if (s.name != m.name) continue;
      Pair p{&m, {}, {}};
      for (const std::size_t r : rows) {
        p.ux.push_back(s.ux[r]);
        p.uy.push_back(s.uy[r]);
      }
      pairs.push_back(std::move(p));
    }
  if (pairs.empty()) return out;
  for (std::size_t i = 0; i < measured.depth.size(); ++i) {
    const double x = measured.depth[i];
    if (x >= d.front() && x <= d.back()) out.push_back(errorsAt(pairs, d, i, x));
  }
  return out;
}

}  // namespace needlesim::mpm
