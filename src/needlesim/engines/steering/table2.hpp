#pragma once
// Seed 002 Table 2 (measured radii of curvature, 3 needles x 4 gels) with the
// paper's model inputs, and the validation runs of the steering models.
// Missing paper inputs (seed 002 Table 1 came out empty) are documented in
// docs/validation/steering.md.
#include <array>
#include <string>
#include <vector>

namespace needlesim::steering {

struct Table2Case {
  const char* gel;
  double diameter;     // m
  double alpha;        // rad
  double rho_sec[3];   // m, measured per 50 mm section
  double rho_mean;     // m, mean of the sections
  double rho_exp;      // m, fitted over 0-150 mm
  double K_T;          // N/m^2 (seed 002 section 3.1; porcine from eq 13, see docs)
  double P_input;      // N (seed 002 section 5.2)
  double beta_energy;  // beta/alpha of the energy model (section 5.2)
  double beta_tip;     // beta/alpha fitted to tip forces (section 3.1; porcine: 0.17 mean)
};

const std::array<Table2Case, 12>& table2Cases();

struct Table2Row {
  double rho_pred = 0.0;         // m, fitted over the predicted 0-150 mm tip path
  double deflection_pred = 0.0;  // m, final tip deflection
  double deflection_exp = 0.0;   // m, from the measured radius: rho (1 - cos(150 mm / rho))
  int increments = 0;
};

// model: "energy" (default path-window frame, docs/models/bevel-tip-energy.md), "energy-entry"
// (the literal eq 45 frame), "energy-window-tip-beta" (section 3.1 beta/alpha),
// "beam-foundation" (tip load = the section-4 roller reaction P_input/tan(beta) with the
// section 5.2 inputs) or "beam-foundation-edges" (tip loads of eqs 24-26 with the section 3.1
// cut angles) or "kinematic" (constant curvature); 150 mm insertion, 1 mm increments for the
// beam. beta_ratio >= 0 replaces the case's beta/alpha (energy, energy-entry, beam-foundation);
// for "kinematic" a beta_ratio > 0 is the curvature in 1/m (default 1/rho_exp); "radius-proportional"
// (rho = c d, the other baseline) takes c = rho / d in beta_ratio (default rho_exp / d).
Table2Row runTable2Case(const Table2Case& c, const std::string& model, double beta_ratio = -1.0);

// The beta/alpha in (0, 1] for which `model` ("energy" or "beam-foundation") reproduces the
// measured 0-150 mm radius rho_exp of case c (bisection on the monotone radius; returns 1
// or ~0 when the measurement lies outside the model's reach).
double calibrateBetaRatio(const Table2Case& c, const std::string& model);

// Leave-two-out prediction per gel: beta/alpha calibrated on the needle `calibration`
// (0, 1, 2 = 0.36, 0.46, 0.54 mm) of each gel predicts the other two needles of that gel.
// model "kinematic" = the same curvature 1/rho_exp(calibration needle) for every needle of the gel;
// "radius-proportional" = rho = (rho_exp / d)(calibration needle) x d.
struct Table2Prediction {
  int case_index = 0;       // into table2Cases()
  int calibration_case = 0; // the case the parameter was fitted on
  double beta_ratio = 0.0;  // fitted beta/alpha (kinematic: curvature, 1/m; radius-proportional: rho/d)
  double rho_pred = 0.0;    // m
  double error = 0.0;       // (rho_pred - rho_exp) / rho_exp
};
std::vector<Table2Prediction> table2CrossValidation(const std::string& model, int calibration);

}  // namespace needlesim::steering
