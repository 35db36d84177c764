#pragma once
// The strain energy of a law as a function of the invariants (J, I1, I2,
// h_p = tr C^(alpha_p/2)), instantiated with detail::Ad2 for exact first and
// second derivatives (stress and tangent): the formula of the law's unit in
// laws/. Internal to the materials library. See docs/models/materials.md.
#include <tuple>

#include "needlesim/materials/hyperelastic.hpp"
#include "needlesim/materials/laws/law_unit.hpp"
#include "needlesim/materials/second_order_ad.hpp"

namespace needlesim::materials::detail {

// Full energy from (J, I1, I2, h[p] = tr C^(alpha_p/2)) of C = F^T F.
template <class T>
T totalEnergy(const Hyperelastic& m, const T& J, const T& I1, const T& I2, const T* h) {
  return std::get<EnergyFn<T>>(lawUnit(m.kind).energy)(m, J, I1, I2, h);
}

}  // namespace needlesim::materials::detail
