// Velocity conditions on the MPM background grid (grid_boundaries.hpp).
#include "needlesim/engines/mpm/grid_boundaries.hpp"

#include <cmath>

namespace needlesim::mpm {

// The conditions on the nodes on or beyond each face of the box, the held
// nodes, and the dashpots of the non-reflecting faces (the first material's
// wave impedances).
void GridBoundaries::build(const MpmConfig& cfg, const int* nn, const MpmMaterial* m0) {
  const std::size_t nodes = static_cast<std::size_t>(nn[0]) * nn[1] * nn[2];
  fixMask.assign(nodes, 0);
  dashpot.assign(3 * nodes, 0.0);
  const double tol = 1e-6 * cfg.h;
  double rho = 0, cp = 0, cs = 0;
  if (m0) {
    rho = m0->density * cfg.massScaling;
    const double K = m0->law.initialBulk(), mu = m0->law.initialShear();
    cp = std::sqrt((K + 4.0 / 3.0 * mu) / rho);
    cs = std::sqrt(mu / rho);
  }
  for (int i = 0; i < nn[0]; ++i)
    for (int j = 0; j < nn[1]; ++j)
      for (int k = 0; k < nn[2]; ++k) {
        const std::size_t I = (static_cast<std::size_t>(i) * nn[1] + j) * nn[2] + k;
        const int idx[3] = {i, j, k};
        for (int f = 0; f < 6; ++f) {
          const int d = f / 2;
          const double x = cfg.origin[d] + idx[d] * cfg.h;
          const bool beyond = (f % 2 == 0) ? x <= cfg.boxLo[d] + tol : x >= cfg.boxHi[d] - tol;
          if (!beyond) continue;
          switch (cfg.faces[static_cast<std::size_t>(f)]) {
            case FaceBC::Fixed: fixMask[I] |= 7; break;
            case FaceBC::Roller: fixMask[I] |= static_cast<std::uint8_t>(1 << d); break;
            case FaceBC::NonReflecting: {
              // Lysmer-Kuhlemeyer dashpots on the face nodes (tributary area h^2).
              const bool onFace = std::abs(x - ((f % 2 == 0) ? cfg.boxLo[d] : cfg.boxHi[d])) < 0.5 * cfg.h;
              if (!onFace) break;
              for (int c = 0; c < 3; ++c)
                dashpot[3 * I + c] += rho * (c == d ? cp : cs) * cfg.h * cfg.h;
              break;
            }
            case FaceBC::Free: break;
          }
        }
      }
  for (const auto& n : cfg.heldNodes) {
    if (n[0] < 0 || n[1] < 0 || n[2] < 0 || n[0] >= nn[0] || n[1] >= nn[1] || n[2] >= nn[2]) continue;
    fixMask[(static_cast<std::size_t>(n[0]) * nn[1] + n[1]) * nn[2] + n[2]] |= 7;
  }

}

}  // namespace needlesim::mpm
