// Average nodal pressure for the constant-strain tri3 / tet4 (docs/models/explicit.md,
// "Elements"): Bonet & Burton 1998 (Commun. Numer. Meth. Eng. 14, 437-449), Bonet, Marriott
// & Hassan 2001 (IJNME 50, 119-133). The volumetric energy is taken at the nodes,
// U = sum_a V_a U(J_a), J_a = sum_{e∋a} (V_e / n) J_e / V_a, V_a = sum_{e∋a} V_e / n; its
// forces are f_b = sum_e pbar_e v_e grad_x N_b with pbar_e the mean of the nodal pressures
// p_a = U'(J_a) of the element's nodes. With U = K/2 (J - 1)^2 (the library's volumetric
// term), p_a = K (J_a - 1) is the V_e-weighted mean of the element pressures, which is what is
// computed here from each element's Cauchy mean stress (any law): the element keeps its
// deviatoric stress and replaces its pressure p_e by pbar_e,
//   f_a += (pbar_e - p_e) V0 J F^-T grad0 N_a.
// The incompressibility constraint is then one per node instead of one per element, so the
// elements do not lock at nu -> 1/2 (test ExplicitNodalPressure.*); a homogeneous state has
// pbar_e = p_e (patch test unchanged).
#include "needlesim/engines/explicit/solver.hpp"

namespace needlesim::explicit_fe {

double ExplicitSolver::nodalPressureCorrection() {
  const int npe = npe_, d = dim_;
  constexpr int kParallel = 4000;
  double dE = 0.0;  // stored energy: + sum_a V_a p_a^2 / 2K - sum_e V_e p_e^2 / 2K (exact for K/2 (J-1)^2)
#pragma omp parallel for schedule(static) if (nnode_ >= kParallel) reduction(+ : dE)
  for (int n = 0; n < nnode_; ++n) {
    double pv = 0.0, v = 0.0, vk = 0.0;
    for (int k = nodeStart_[n]; k < nodeStart_[n + 1]; ++k) {
      const int e = nodeSlots_[k] / npe;
      pv += vol0_[e] * anpP_[e];
      v += vol0_[e];
      vk += vol0_[e] / (npe * matBulk_[mat_[e]]);
    }
    anpNode_[n] = v > 0 ? pv / v : 0.0;
    dE += 0.5 * vk * anpNode_[n] * anpNode_[n];
  }
#pragma omp parallel for schedule(static) if (nel_ >= kParallel) reduction(+ : dE)
  for (int e = 0; e < nel_; ++e) {
    dE -= 0.5 * vol0_[e] * anpP_[e] * anpP_[e] / matBulk_[mat_[e]];
    const int* cn = &mesh_.conn[static_cast<std::size_t>(e) * npe];
    double pbar = 0.0;
    for (int a = 0; a < npe; ++a) pbar += anpNode_[cn[a]];
    pbar /= npe;
    const double dp = pbar - anpP_[e];
    double* fe = &fe_[static_cast<std::size_t>(e) * npe * d];
    const double* b = &anpB_[static_cast<std::size_t>(e) * npe * d];
    for (int k = 0; k < npe * d; ++k) fe[k] += dp * b[k];
    anpDp_[e] = dp;  // the output stress adds dp I to the Cauchy stress (cellFields)
  }
  return dE;
}

}  // namespace needlesim::explicit_fe
