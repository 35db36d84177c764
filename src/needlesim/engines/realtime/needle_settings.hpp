#pragma once
// Needle and layer force settings shared by the real-time engines (realtime2d, realtime3d).
#include <cmath>
#include <string>
#include <vector>

#include "needlesim/core/error.hpp"
#include "needlesim/needle/insertion_frame.hpp"

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
  KarnoppFriction friction;    // per unit length (eq 3.23); D_p, D_n as given (contact/karnopp.hpp)
  double cutting_force = 0.0;  // N (eq 3.24)
  // N, threshold of eq 3.16 (with the layer's E, nu) at the layer's near boundary; the
  // first layer's is the session's puncture_force.
  double puncture_force = 0.0;
};

// A real-time session's settings around its tissue (TissueConfig of realtime2d or realtime3d).
template <class TissueConfigT>
struct SessionSettings {
  TissueConfigT tissue;
  NeedleConfig needle;
  KarnoppFriction friction;    // per unit length (eq 3.23); D_p, D_n as given (contact/karnopp.hpp)
  double cutting_force = 0.0;  // N (eq 3.24)
  // Optional layered forces: when not empty they replace `friction` and `cutting_force`,
  // by the depth x of each path node (friction) and of the tip (cutting).
  std::vector<LayerForces> layers;
  double puncture_force = 0.0; // N, threshold of eq 3.16 at the entry face
  // The insertion frame (needle/insertion_frame.hpp) in the centred tissue frame: entry point,
  // reference axis, lateral, out of plane, bevel orientation (realtime2d uses the in-plane parts).
  needle::InsertionFrame frame;
  double dt = 1e-3;            // s
  int max_active_set_iterations = 12;
};

// Refusals common to the real-time sessions: the needle beam, the step, Newmark gamma
// (seed 003 eqs 3.2-3.4: gamma < 1/2 amplifies every mode; beta below (gamma + 1/2)^2 / 4 is only
// conditionally stable and is checked against the mesh in TissueDynamics).
template <class Settings>
void checkSessionSettings(const Settings& c, const std::string& engine) {
  if (!(c.needle.EI > 0.0) || !(c.needle.length > 0.0))
    throw SolverError(engine + ": the needle needs EI > 0 and length > 0");
  if (!(c.dt > 0.0)) throw SolverError(engine + ": the time step must be > 0");
  if (c.tissue.newmark.gamma < 0.5)
    throw SolverError(engine + ": Newmark gamma = " + std::to_string(c.tissue.newmark.gamma) +
                      " < 1/2 is unstable (negative numerical damping); use gamma >= 0.5");
}

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
