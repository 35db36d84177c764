// F-bar anti-locking of the MPM solver (model.mpm.anti_locking: fbar): the
// stress at the cell-averaged volume change.
#include <algorithm>
#include <cmath>

#include <Eigen/LU>

#include "needlesim/engines/mpm/mpm_solver.hpp"

namespace needlesim::mpm {

// Anti-locking (F-bar, de Souza Neto et al. 1996, in the MPM form of cell
// averages): the volume change of every particle is replaced by the average
// over the particles in its grid cell, Jbar = sum V0 J / sum V0 (current over
// reference volume), and the stress is evaluated at Fbar = (Jbar / J)^(1/3) F.
// One volumetric constraint per cell instead of one per particle, so a nearly
// incompressible law (nu -> 0.5) no longer locks the 8 points of a cell; the
// deviatoric part of F is the particle's own. The stored F stays the true one.
void MpmSolver::fbarStress(double& eiOut, double& vmaxOut) {
  const std::size_t np = size();
  const double invh = 1.0 / cfg_.h;
  const double ox = cfg_.origin.x(), oy = cfg_.origin.y(), oz = cfg_.origin.z();
  const std::size_t n1 = static_cast<std::size_t>(nn_[1]), n2 = static_cast<std::size_t>(nn_[2]);
  cellOf_.resize(np);
  cellJ_.assign(2 * nodes_, 0.0);
  for (std::size_t p = 0; p < np; ++p) {  // serial: one multiply-add per particle
    const auto i = static_cast<std::size_t>((P_[p].x[0] - ox) * invh), j = static_cast<std::size_t>((P_[p].x[1] - oy) * invh),
               k = static_cast<std::size_t>((P_[p].x[2] - oz) * invh);
    const std::size_t c = (i * n1 + j) * n2 + k;  // cell by its lower node (inside: checked in g2pFinal)
    cellOf_[p] = static_cast<std::uint32_t>(c);
    cellJ_[2 * c] += P_[p].vol0 * defGrad(p).determinant();
    cellJ_[2 * c + 1] += P_[p].vol0;
  }
  double ei = 0.0, vmax = 0.0;
#pragma omp parallel for schedule(static) num_threads(nthreads_) reduction(+ : ei) reduction(max : vmax)
  for (std::size_t p = 0; p < np; ++p) {
    const std::size_t c = cellOf_[p];
    const Mat3 F = defGrad(p);
    const double Jbar = cellJ_[2 * c] / cellJ_[2 * c + 1];
    const Mat3 Fbar = std::cbrt(Jbar / F.determinant()) * F;
    double W, w;
    stress(p, Fbar, W, w);
    ei += P_[p].vol0 * W;
    vmax = std::max(vmax, w + std::sqrt(P_[p].v[0] * P_[p].v[0] + P_[p].v[1] * P_[p].v[1] + P_[p].v[2] * P_[p].v[2]));
  }
  eiOut += ei;
  vmaxOut = std::max(vmaxOut, vmax);
}

}  // namespace needlesim::mpm
