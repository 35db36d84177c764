#pragma once
// Analyses of needle insertion-force logs: rupture toughness G_c (seed 002
// eqs 14-19, seed 004 eqs 11-13), cohesive strength t_c = 2 G_c / delta_c
// (seed 004 section IV.A), interaction stiffness K_T (seed 002 eqs 11-13),
// friction and cutting parameters from insertions at several speeds (seed 003
// eqs 5.1-5.5, as one least-squares problem), and puncture depth and force.
// Depth is the needle-tip depth below the tissue surface (m), force the axial
// insertion force (N, positive resisting insertion).
#include <string>
#include <vector>

#include "needlesim/io/csv_reader.hpp"

namespace needlesim::fit {

struct InsertionLog {
  std::string file;
  std::vector<double> depth, force;  // m, N
  std::vector<int> lines;
  double speed = 0.0;  // m/s (from a speed column, a time column, or given)
};

// Reads depth|position|displacement [length] and force [N], optionally time [s]
// or speed [velocity]. A speed column with several values splits the file into
// one log per speed. speedOverride > 0 replaces the speed of every log.
std::vector<InsertionLog> readInsertionLogs(const io::CsvData& csv, double speedOverride = 0.0);

// ---- puncture ----
struct Puncture {
  bool found = false;
  double depth = 0.0;      // m, depth of the force peak before the drop
  double force = 0.0;      // N, peak force
  double drop = 0.0;       // N, force lost right after the peak
  double stiffness = 0.0;  // N/m, least-squares slope F = k z before the peak
  int line = 0;
};
// The first peak after which the force falls by more than dropFraction of the peak
// and by more than 6 times the noise level (median absolute first difference).
Puncture detectPuncture(const InsertionLog& log, double dropFraction = 0.2);

// ---- rupture toughness ----
struct ToughnessOptions {
  double diameter = 0.0;      // m, needle diameter (A = pi d^2 / 4)
  double shaftLength = 0.0;   // m, L2: tissue thickness = shaft length inside once the tip exits
  double windowStart = -1.0;  // m, start of the L1 window; < 0: the puncture depth (or 0)
  double windowLength = 0.0;  // m, L1; 0: up to the exit (L2)
  bool literalEq12 = false;   // F2' = F2 L1/L2 held constant over the window (literal eq 12)
};
struct ToughnessResult {
  double area = 0.0;         // m^2
  double L1 = 0.0, L2 = 0.0;  // m
  double windowStart = 0.0;  // m
  double F2 = 0.0;           // N, mean force once the tip has exited
  double frictionPerLength = 0.0;  // N/m, k = F2 / L2 (seed 002 eq 15)
  double Gftc = 0.0, Gft = 0.0, Gc = 0.0;  // J/m^2 (= N/m)
};
ToughnessResult ruptureToughness(const InsertionLog& log, const ToughnessOptions& opt);
// Seed 004 section IV.A: t_c = 2 G_c / delta_c (linear traction-separation law).
double cohesiveStrength(double Gc, double deltaC);

// ---- interaction stiffness (seed 002 eqs 11-13) ----
// K_T = E_T a / (h c) for a cylinder of diameter d, height h (a = pi d^2/4, c = pi d).
double interactionStiffnessFromModulus(double E, double diameter, double height);
// K_T = 6 C10 a / (h c) = 3/2 C10 d / h (eq 13).
double interactionStiffness(double C10, double diameter, double height);

// ---- friction and cutting (seed 003 eq 5.1: F = F_cut + l (C_p + b_p v)) ----
struct FrictionRow {
  double speed = 0.0;    // m/s
  double force = 0.0;    // N, measured force at full shaft contact length
  double cutting = 0.0;  // N, cutting force at that speed
  double length = 0.0;   // m, shaft length in contact
  int line = 0;
};
struct FrictionFit {
  double C = 0.0, b = 0.0;      // N/m, N s/m^2
  double seC = 0.0, seB = 0.0;  // standard errors (NaN with no redundancy)
  std::vector<double> speeds;   // per run (logs) or per row (summaries)
  std::vector<double> cutting, seCutting;  // N, per speed (or one value, constant model)
  int n = 0;
  double rmse = 0.0;  // N
  std::vector<std::vector<double>> depth, measured, fitted;  // per run, for plots
};
// Least squares over all rows of (F - F_cut) = l (C + b v); two rows give the
// pairwise solution of seed 003 (eqs 5.2-5.5).
FrictionFit frictionFromSummaries(const std::vector<FrictionRow>& rows, const std::string& file = "");
std::vector<FrictionRow> readFrictionSummaries(const io::CsvData& csv);

enum class CuttingModel { Constant, PerSpeed, Linear };
// One linear least-squares problem over every point of every run, after each
// run's puncture: F = F_cut(v) [tip inside] + min(z, thickness) (C + b v).
// thickness <= 0: the tip never exits.
FrictionFit fitFrictionCutting(const std::vector<InsertionLog>& logs, double thickness,
                               CuttingModel cutting = CuttingModel::PerSpeed);

}  // namespace needlesim::fit
