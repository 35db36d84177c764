#pragma once
// Surface position of a body seen from one grid node, estimated from the mass
// centroid of its field at that node (two-body gap rule of the grid contact,
// seed 000 eqs 14-21; docs/models/mpm.md "Gap rule for two bodies").
//
// A body filling the half-space xi < s (xi: coordinate along the contact
// normal from the node, in cells) maps to the node a mass centroid
//   c(s) = int_{-inf}^{s} xi w(xi) dxi / int_{-inf}^{s} w(xi) dxi,
// with w the 1D shape function (linear hat or quadratic B-spline; the
// transverse factors cancel for a face normal to an axis). c is increasing in
// s, so the measured centroid gives the surface s = c^{-1}(c_measured) at
// every node, not only at nodes on the interface: contact when the two
// estimated surfaces meet, wherever the node lies. Exact for a face normal to
// a grid axis and a uniform density; for an oblique face the tensor-product
// kernel is not the 1D one along n and the estimate is approximate (within a
// fraction of a cell), as is the particle quadrature of the integrals.
#include <algorithm>
#include <array>
#include <cmath>

namespace needlesim::mpm {

class SurfaceFromCentroid {
 public:
  // support: 1 (linear hat) or 1.5 (quadratic B-spline), in cells.
  explicit SurfaceFromCentroid(bool bspline) : r_(bspline ? 1.5 : 1.0), bspline_(bspline) {
    // Tabulate c(s) on kN points of s in (-r, r] by midpoint quadrature.
    constexpr int kQ = 4000;
    const double dq = 2.0 * r_ / kQ;
    for (int i = 0; i < kN; ++i) {
      s_[i] = -r_ + 2.0 * r_ * (i + 1) / kN;
      double m = 0, mx = 0;
      for (int q = 0; q < kQ; ++q) {
        const double xi = -r_ + (q + 0.5) * dq;
        if (xi > s_[i]) break;
        const double w = weight(xi);
        m += w * dq;
        mx += xi * w * dq;
      }
      c_[i] = m > 0 ? mx / m : -r_;
    }
  }
  // Surface (in cells from the node) of a body on the negative side whose
  // centroid is at c cells from the node; saturates at +-r.
  double surface(double c) const {
    if (c <= c_[0]) return s_[0];
    if (c >= c_[kN - 1]) return r_;
    const int i = static_cast<int>(std::upper_bound(c_.begin(), c_.end(), c) - c_.begin());
    const double t = (c - c_[i - 1]) / (c_[i] - c_[i - 1]);
    return s_[i - 1] + t * (s_[i] - s_[i - 1]);
  }

 private:
  double weight(double xi) const {
    const double a = std::abs(xi);
    if (!bspline_) return a < 1.0 ? 1.0 - a : 0.0;
    if (a < 0.5) return 0.75 - a * a;
    if (a < 1.5) return 0.5 * (1.5 - a) * (1.5 - a);
    return 0.0;
  }
  static constexpr int kN = 256;
  double r_;
  bool bspline_;
  std::array<double, kN> s_{}, c_{};
};

}  // namespace needlesim::mpm
