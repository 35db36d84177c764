#pragma once
// Needle and layer force settings shared by the real-time engines (realtime2d, realtime3d).
#include <cmath>

#include "needlesim/engines/realtime/tip_forces.hpp"
#include "needlesim/scenario/scenario.hpp"

namespace needlesim::realtime {

struct NeedleConfig {
  double length = 0.1;          // m, base (hub, clamped) to tip
  double EI = 0.0;              // N m^2, bending stiffness
  double bevel_angle = 0.5236;  // rad, tip (bevel) angle alpha
  // Transverse bevel load Q / cutting force; < 0 selects the wedge estimate cot(alpha)
  // (the bevel face carries the cutting force: axial N sin a = F_cut, lateral N cos a).
  double tip_load_ratio = -1.0;
  double tipLoadRatio() const { return tip_load_ratio >= 0.0 ? tip_load_ratio : 1.0 / std::tan(bevel_angle); }
};

// Forces of one layer of a layered block (depth bands from the entry face).
struct LayerForces {
  double depth_end = 0.0;      // m, x of the layer's far boundary
  FrictionSpec friction;       // per unit length (eq 3.23); D = 0 defaults to C
  double cutting_force = 0.0;  // N (eq 3.24)
  // N, threshold of eq 3.16 (with the layer's E, nu) at the layer's near boundary; the
  // first layer's is the session's puncture_force.
  double puncture_force = 0.0;
};

enum class Phase : int { Outside = 0, Pressing = 1, Cutting = 2, Inside = 3, Through = 4 };

// Phase of the insertion from the tip's state; band = half the static band (m/s).
inline Phase phaseOf(const TipForces& tip, const AxialMotion& mo, double Fc, double s_exit, double band) {
  if (mo.s_tip <= 0.0) return Phase::Outside;
  if (!tip.entered() || tip.pressing()) return Phase::Pressing;
  if (mo.s_tip >= s_exit) return Phase::Through;
  if (Fc > 0.0 && mo.v_ax >= band) return Phase::Cutting;
  return Phase::Inside;
}

}  // namespace needlesim::realtime
