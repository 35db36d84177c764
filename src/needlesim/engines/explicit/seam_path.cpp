#include "needlesim/engines/explicit/seam_path.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "needlesim/core/error.hpp"

namespace needlesim::explicit_fe {

double pathHeight(const std::vector<Eigen::Vector2d>& p, double x) {
  if (p.size() < 2) throw Error("crack path: needs at least 2 points");
  for (std::size_t i = 1; i < p.size(); ++i)
    if (!(p[i].x() > p[i - 1].x())) throw Error("crack path: the x coordinates must increase along the path");
  if (x <= p.front().x()) return p.front().y();
  if (x >= p.back().x()) return p.back().y();
  const auto it = std::upper_bound(p.begin(), p.end(), x, [](double v, const Eigen::Vector2d& q) { return v < q.x(); });
  const Eigen::Vector2d& b = *it;
  const Eigen::Vector2d& a = *(it - 1);
  return a.y() + (b.y() - a.y()) * (x - a.x()) / (b.x() - a.x());
}

void morphOntoPath(Mesh& m, double lineY, const std::vector<Eigen::Vector2d>& path, double band, double plateau) {
  if (m.dim != 2) throw Error("crack path: the path morph is 2D only");
  if (!(band > 0)) throw Error("crack path: the morph band must be > 0");
  if (!(plateau >= 0 && plateau < band)) throw Error("crack path: the morph plateau must lie in [0, band)");
  const int nn = m.nodes();
  std::vector<double> X0 = m.X;
  for (int n = 0; n < nn; ++n) {
    const double x = X0[2 * n], y = X0[2 * n + 1];
    const double dy = std::abs(y - lineY);
    const double w = plateau > 0.0 ? (dy <= plateau ? 1.0 : std::max(0.0, 1.0 - (dy - plateau) / (band - plateau)))
                                   : std::max(0.0, 1.0 - dy / band);
    m.X[2 * n + 1] = y + w * (pathHeight(path, x) - lineY);
  }
  // no folded element: every quad / triangle keeps a positive signed area
  const int npe = nodesPerElement(m.type);
  for (int e = 0; e < m.elements(); ++e) {
    for (int k = 0; k < npe; ++k) {
      const int a = m.conn[e * npe + k], b = m.conn[e * npe + (k + 1) % npe], c = m.conn[e * npe + (k + 2) % npe];
      auto area = [&](const std::vector<double>& X) {
        return (X[2 * b] - X[2 * a]) * (X[2 * c + 1] - X[2 * a + 1]) - (X[2 * b + 1] - X[2 * a + 1]) * (X[2 * c] - X[2 * a]);
      };
      if (area(m.X) * area(X0) <= 0)
        throw Error("crack path: moving the grid line y = " + std::to_string(lineY) +
                    " m onto the path folds element " + std::to_string(e) +
                    " (the path departs too far or too steeply from the line for the morph band " +
                    std::to_string(band) + " m)");
    }
  }
}

}  // namespace needlesim::explicit_fe
