#pragma once
// Prony-series viscoelasticity on any hyperelastic law: seed 001 eqs 1-4 (the
// "modified Kelvin-Voigt" model) read as quasi-linear viscoelasticity (QLV)
// with internal variables,
//   S(t) = int_0^t G(t - s) dS_e/ds ds,   G(t) = 1 - sum_i g_i (1 - exp(-t/tau_i))   (seed 001 eq 3)
// where S_e is the elastic (instantaneous) stress of the hyperelastic law.
// With H_i(t) = int exp(-(t - s)/tau_i) dS_e, S = g_inf S_e + sum_i g_i H_i, and the
// update over a step dt, exact when S_e varies linearly within the step,
//   H_i <- exp(-dt/tau_i) H_i + (1 - exp(-dt/tau_i)) / (dt/tau_i) (S_e_new - S_e_old),
// is unconditionally stable: both factors lie in [0, 1] for every dt >= 0.
#include <cmath>
#include <string>
#include <vector>

#include "needlesim/materials/material_spec.hpp"

namespace needlesim::materials {

struct Prony {
  std::vector<PronyTerm> terms;

  double gInfinity() const;                 // 1 - sum g_i (long-term relative modulus)
  double relaxation(double t) const;        // G(t) for t >= 0 (G(0) = 1)
  // Factor of the algorithmic tangent over a step dt: dS_new/dS_e_new.
  double stepFactor(double dt) const;
  // Throws Error naming the term if g_i < 0, tau_i <= 0, sum g_i >= 1 or non-finite.
  void validate() const;
};

// (1 - exp(-x)) / x, accurate near x = 0 (x = dt/tau >= 0).
inline double phi1(double x) { return x < 1e-8 ? 1.0 - 0.5 * x : -std::expm1(-x) / x; }

// Internal state of one material point: H_i per term and the previous elastic stress.
// Vec is any Eigen vector (e.g. Voigt stress) or double.
template <class Vec>
struct PronyState {
  std::vector<Vec> H;
  Vec SePrev{};
  bool started = false;
};

// Advances the state by dt to the new elastic stress SeNew and returns the
// viscoelastic stress. The first call starts from a stress-free history.
template <class Vec>
Vec pronyUpdate(const Prony& prony, PronyState<Vec>& st, const Vec& SeNew, double dt) {
  const std::size_t n = prony.terms.size();
  if (!st.started) {
    st.H.assign(n, SeNew * 0.0);
    st.SePrev = SeNew * 0.0;
    st.started = true;
  }
  Vec dSe = SeNew - st.SePrev;
  Vec out = prony.gInfinity() * SeNew;
  for (std::size_t i = 0; i < n; ++i) {
    const double x = dt / prony.terms[i].tau;
    st.H[i] = std::exp(-x) * st.H[i] + phi1(x) * dSe;
    out = out + prony.terms[i].g * st.H[i];
  }
  st.SePrev = SeNew;
  return out;
}

}  // namespace needlesim::materials
