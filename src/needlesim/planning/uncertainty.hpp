#pragma once
// The targeting error of a plan under the scenario's stated spreads, by Monte Carlo over the
// kinematic model (docs/planning.md): open loop (the plan executed as it is) and closed loop
// (a noisy tip and target measurement every measure_every of insertion, the last arc replanned
// from it, the tip pulled back along its channel and steered anew where the target is out of
// its reach).
#include <vector>

#include "needlesim/planning/plan_problem.hpp"
#include "needlesim/scenario/plan_section.hpp"

namespace needlesim::planning {

struct ErrorDistribution {
  std::vector<double> errors;   // m, tip-to-target distance at the end, per sample
  std::vector<char> touched;    // per sample: the needle touched an obstacle (axis within its radius)
  double p50 = 0.0, p95 = 0.0;  // m
  double touch_probability = 0.0;
  double mean_rotations = 0.0;  // axial rotations per insertion (closed loop: with the corrections)
  // closed loop with plan.max_retractions > 0: per sample, the retractions and the depth the
  // first pulled the tip back to (0 without); their mean, the share of samples retracting, the
  // mean depth retracted to, and the actions executed by the first sample that retracted
  std::vector<int> retractions;
  std::vector<double> retracted_to;
  double mean_retractions = 0.0, retracting_share = 0.0, mean_retracted_to = 0.0;
  Plan retracting_example;
};

// One drawn execution: the curvature factor, the entry error and the target's displacement.
struct Draw {
  double curvature_scale = 1.0;
  Vec3 entry_shift = Vec3::Zero();  // m, on the entry face (y, z)
  double tilt_y = 0.0, tilt_z = 0.0;  // rad, entry direction errors about the tissue's y and z axes
  Vec3 target_shift = Vec3::Zero();
};

// The open-loop error distribution of `plan`.
ErrorDistribution openLoopErrors(const PlanProblem& pb, const Plan& plan, const PlanUncertaintySpec& u);
// The closed-loop error distribution (u.measure_every > 0).
ErrorDistribution closedLoopErrors(const PlanProblem& pb, const Plan& plan, const PlanUncertaintySpec& u);

// The quantile q of values (linear between order statistics).
double quantile(std::vector<double> values, double q);

}  // namespace needlesim::planning
