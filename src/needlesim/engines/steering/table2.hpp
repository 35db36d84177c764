#pragma once
// Seed 002 Table 2 (measured radii of curvature, 3 needles x 4 gels) with the
// paper's model inputs, and the validation runs of the steering models.
// Missing paper inputs (seed 002 Table 1 came out empty) are documented in
// docs/validation/steering.md.
#include <array>
#include <string>

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

// model: "energy", "beam-foundation" (tip load = the section-4 roller reaction P_input/tan(beta)
// with the section 5.2 inputs) or "beam-foundation-edges" (tip loads of eqs 24-26 with the
// section 3.1 cut angles); 150 mm insertion, 1 mm increments for the beam.
Table2Row runTable2Case(const Table2Case& c, const std::string& model);

}  // namespace needlesim::steering
