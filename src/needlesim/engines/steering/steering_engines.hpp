#pragma once
// The steering engines "kinematic", "energy" and "beam-foundation": they read the
// common scenario sections (needle, first tissue layer, insertion profile with bevel
// rotations, spinning and duty cycling) and model.steering, run the models of this
// folder and report the tip path, needle shapes, tip loads, fitted radii of curvature
// (seed 002 section 5.1) and the dimensional analysis (seed 002 eqs 1-3, seed 004
// eqs 1-3). Coordinates: the needle's entry frame, z along the insertion axis at
// entry, y in the insertion plane (bevel orientation 0 steers towards -y), x out of it.
#include <string>
#include <vector>

#include "needlesim/engines/engine.hpp"
#include "needlesim/engines/steering/kinematic.hpp"
#include "needlesim/needle/bevel_tip.hpp"
#include "needlesim/needle/insertion_frame.hpp"
#include "needlesim/needle/section.hpp"

namespace needlesim::engines {

void runKinematic(const Scenario& scenario, ResultSink& sink, const RunOptions& options);
void runEnergy(const Scenario& scenario, ResultSink& sink, const RunOptions& options);
void runBeamFoundation(const Scenario& scenario, ResultSink& sink, const RunOptions& options);

// What the three engines read from a scenario (exposed for tests).
struct SteeringInputs {
  needle::Section section;   // E, outer and inner diameter
  double alpha = 0.0;        // rad, bevel angle
  double beta = 0.0;         // rad, cut angle = beta_over_alpha * alpha (0 for a symmetric tip)
  double K_T = 0.0;          // N/m^2, interaction stiffness (layer, else 1.5 C10: eq 13 with d/h = 1)
  bool K_T_from_material = false;
  double C10 = 0.0;          // Pa, small-strain shear modulus / 2
  double E_T = 0.0, nu_T = 0.0;  // tissue small-strain Young's modulus and Poisson ratio
  double Gc = 0.0;           // J/m^2, 0 = not given
  double mu = 0.0;           // friction coefficient of the layer
  double P_input = 0.0;      // N
  needle::TipLoads tip;      // eqs 24-26 at beta
  double roller_Q = 0.0;     // N, -P_input / tan(beta): sub-step-1 roller reaction, towards -y
  double Q = 0.0, M = 0.0, P = 0.0;  // loads applied by beam-foundation (bevel frame, Fig 13)
  double kappa_bof = 0.0;    // 1/m, (M + Q/lambda)/EI, towards +y of the bevel frame
  double start = 0.0;        // m, depth of the tip when steering starts (straight before)
  double insertion = 0.0;    // m, inserted length the plan covers
  std::vector<steering::Control> plan;  // rotations, spinning, duty cycling per inserted length
  // The shared frame (needle/insertion_frame.hpp). The models work in their own frame
  // (z along the entry axis, y in the insertion plane, x out of it; bevel 0 steers to -y)
  // and report in the tissue frame: entry + z axial + y lateral - x outOfPlane.
  needle::InsertionFrame frame;
  std::vector<std::string> notes;
  units::DisplayUnits display;  // the scenario's display units, for lengths written in notes
};

// Throws InputError for what the steering engines cannot run (no insertion into the
// tissue, in-plane rotations, a 90 deg bevel, duty cycling without a spin rate).
SteeringInputs steeringInputs(const Scenario& sc);

// How the three engines step (engines/step_guard.hpp): in depth, by
// model.steering.increment, and twice per duty cycle; the speed does not enter.
StepPlan steeringStepPlan(const Scenario& sc);
// The energy model's plan, after its own refusals (2D: flips only, at least 1 mm inserted).
StepPlan energyStepPlan(const Scenario& sc);

// Bevel orientation (rad) after `s` metres of insertion along the plan.
double bevelAngleAt(const std::vector<steering::Control>& plan, double s);

}  // namespace needlesim::engines
