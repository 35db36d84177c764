#pragma once
// Energy-based incremental deflection model of seed 002 section 4 (eqs 27-49):
// per insertion increment a roller-constrained push (sub-step 1, potential
// Lambda_1 of eq 30) and the release of the tip reactions (sub-step 2, Lambda_2
// of eq 31), each minimised with Rayleigh-Ritz over the piecewise Hermite trial
// functions of eqs 45-48. The choices where the paper is silent are documented
// in docs/models/bevel-tip-energy.md; the comments cite them as [choice N].
#include <span>
#include <vector>

#include <Eigen/Core>

namespace needlesim::steering {

// Where the Ritz trial functions live [choice 9, docs/models/bevel-tip-energy.md]:
// Entry = the paper's eq 45 literally, two Hermite pieces over the whole inserted
// length clamped at the entry; PathWindow = Hermite pieces over a window of
// `window` foundation lengths (4 EI/K_T)^(1/4) behind the tip, in a frame attached
// to the cut path and clamped to it at the window base.
enum class EnergyFrame { Entry, PathWindow };

struct EnergyParams {
  double E = 50e9;          // Pa, needle Young's modulus (Nitinol, seed 002 section 5.2)
  double diameter = 0.0;    // m, needle diameter (solid)
  double inner_diameter = 0.0;  // m, 0 = solid
  double alpha = 0.0;       // rad, bevel angle
  double beta_ratio = 0.0;  // beta/alpha, cut-angle ratio (seed 002 section 5.2)
  double K_T = 0.0;         // N/m^2, interaction stiffness (eq 13)
  double P_input = 0.0;     // N, insertion force
  double friction_fraction = 0.0;  // share of input work dissipated by friction (Fig 23)
  double Gc = 0.0;          // J/m^2, effective rupture toughness of eq 19 (dimensional groups only)
  // J/m^2, fracture energy per unit torn area that W_R = a G_f l (eq 44) charges per unit
  // advance [choice 5]; default inferred from seed 002 Fig 23 (docs/models/bevel-tip-energy.md)
  double fracture_energy = 0.44;
  double tear_length = -1;  // m, a in eq 44; < 0 = the needle radius [choice 5]
  double E_T = 0.0, nu_T = 0.45, medium_volume = 0.0;  // for U_C (eq 39), reporting only
  double insertion = 0.150;  // m, insertion distance to simulate
  double initial_length = 1e-3;  // m, l_0 [choice 6]
  double max_step = 1e-3;   // m, cap on the advance of one increment [choice 4]
  int max_increments = 2000000;
  std::vector<double> flip_depths;  // m, inserted lengths at which the bevel turns 180 deg
  EnergyFrame frame = EnergyFrame::PathWindow;  // [choice 9]
  double window = 4.0;      // PathWindow: window length in foundation lengths (4 EI/K_T)^(1/4)
  int window_elements = 8;  // PathWindow: Hermite pieces over the window
};

struct EnergyIncrement {
  double length = 0.0;   // m, l_i
  double tip_x = 0.0;    // m, tip position along the insertion axis
  double tip_v = 0.0;    // m, tip deflection v_i(l_i)
  double phi = 0.0;      // rad, tip slope angle (eq 29)
  double P = 0.0, Q = 0.0;  // N, released tip loads (global, sub-step 2; transverse share chi, choice 10)
  double H = 0.0, V = 0.0;  // N, roller reactions (local, eqs 27-28)
  // (v, v') at l/2 and l: the needle shape (PathWindow: the cut path sampled there,
  // a display approximation in the entry frame)
  Eigen::Vector4d coeffs = Eigen::Vector4d::Zero();
};

// Deflection v(x) of the two-piece clamped Hermite shape (eq 45) of length l with
// coefficients c = (v(l/2), v'(l/2), v(l), v'(l)); beyond l it continues straight.
double energyDeflection(const Eigen::Vector4d& c, double l, double x);

struct EnergyResult {
  int increments = 0;
  double final_deflection = 0.0;  // m, tip deflection at the end of the insertion
  double final_length = 0.0;      // m
  // energy bookkeeping summed over the increments (J)
  double W_input = 0.0, W_Q = 0.0, W_P = 0.0, W_R = 0.0, U_B = 0.0, U_T = 0.0, U_C = 0.0;
  double W_friction = 0.0;  // J, input work dissipated along the shaft (Fig 23) [choice 7]
  // share of the tip's input work left for the sideways cut after rupture,
  // chi = max(0, 1 - a G_f / ((1 - f) P_input)) [choice 10]
  double cut_share = 1.0;
  bool capped = false;  // some increment hit max_step
};

// Runs the model. Tip positions (x, v, 0) are appended to `path` every
// `record_every` metres of insertion (and at the end) if path is non-null;
// `increments` (optional) receives every increment. Throws std::invalid_argument
// for non-physical input.
EnergyResult runEnergyModel(const EnergyParams& p, std::vector<Eigen::Vector3d>* path = nullptr,
                            double record_every = 1e-3,
                            std::vector<EnergyIncrement>* increments = nullptr);

}  // namespace needlesim::steering
