#pragma once
// The plan section of a scenario (`needlesim plan`, docs/planning.md): the target, the
// structures to avoid with their clearance, the entry window, what the needle may do, the
// limits and the uncertainty the plan is judged under. Plain structs in SI; each field is
// declared once in plan_section.cpp (scenario/parameter_table.hpp).
#include <limits>
#include <string>
#include <vector>

namespace needlesim {
struct Scenario;

// An inclusion the needle must keep away from, by a clearance (surface to needle axis).
struct PlanAvoidSpec {
  std::string inclusion;   // the name of an inclusion of tissue.inclusions
  double clearance = 1e-3; // m
};

// The spreads the targeting error is predicted under (Monte Carlo), and the closed loop.
struct PlanUncertaintySpec {
  int samples = 0;                 // Monte Carlo samples (0 = no prediction)
  int seed = 1;
  double curvature_sd = 0.0;       // relative standard deviation of the curvature
  double modulus_sd = 0.0;         // relative standard deviation of the tissue's modulus
  double target_sd = 0.0;          // m, standard deviation of the target position, per axis
  double entry_sd = 0.0;           // m, standard deviation of the entry point on the face, per axis
  double angle_sd = 0.0;           // rad, standard deviation of the entry direction, per axis
  double measurement_noise = 0.0;  // m, standard deviation of a tip measurement, per axis
  double measure_every = 0.0;      // m of insertion between tip measurements (0 = open loop)
};

struct PlanSpec {
  bool given = false;  // the scenario has a plan section
  std::string target;  // an inclusion marked target: true; empty = the point below
  double target_depth = std::numeric_limits<double>::quiet_NaN();  // m, tissue frame x
  double target_lateral = 0.0;    // m, tissue frame y
  double target_elevation = 0.0;  // m, tissue frame z
  double tolerance = 1e-3;        // m, largest planned miss distance
  std::vector<PlanAvoidSpec> avoid;
  double entry_window = 0.0;      // m, half-width of the entry window around insertion.entry_offset
  double max_entry_angle = 0.0;   // rad, largest change of insertion.entry_angle
  bool duty_cycling = false;      // the last arc may be duty-cycled to a lower curvature
  double curvature_reserve = 0.0; // share of the curvature kept in hand: arcs planned at (1 - it) kappa
  int max_rotations = 2;          // axial rotations of the bevel during the insertion
  int max_retractions = 0;        // closed loop: retractions along the channel per insertion
  double max_depth = 0.0;         // m, longest insertion (0 = the needle's length)
  double sample_spacing = 5e-4;   // m, spacing of the path points checked against the obstacles
  int max_paths = 200000;         // search budget: candidate paths evaluated
  int seed = 1;                   // random seed of the search
  std::string choose = "clearance";  // clearance | risk
  PlanUncertaintySpec uncertainty;
};

namespace scenario {
class Section;
struct FieldDoc;
// The schema rows of plan, plan_avoid and plan_uncertainty.
std::vector<FieldDoc> planDocs();
// Reads scenario.plan (tissue read before: the target and the obstacles name its inclusions).
void readPlan(Section& plan, Scenario& sc);
}  // namespace scenario

}  // namespace needlesim
