#pragma once
// The path planner: a sampling-based search with an analytic last arc over the kinematic
// bevel-tip model (docs/planning.md). Plans with 0, 1, ... max_rotations axial rotations are
// searched in turn; each candidate samples the entry and the arcs before the last, and one
// free scalar of them (the entry angle, or the length of the arc before the last) is solved
// for so that the last arc, turned towards the target, reaches it with the needle's own
// curvature (or, duty-cycled, with less). The first rotation count with a plan that reaches
// the target within the tolerance, keeps every clearance and stays in the tissue wins.
#include <string>
#include <vector>

#include "needlesim/planning/plan_problem.hpp"

namespace needlesim::planning {

// A path checked against the target, the obstacles and the limits.
struct CheckedPath {
  Plan plan;
  std::vector<Vec3> points;       // the tip path, every sample_spacing or closer
  double miss = 0.0;              // m, distance from the path's end to the target
  std::vector<double> distances;  // m, per obstacle: smallest distance of the axis to its surface
  double margin = 0.0;            // m, smallest (distance - clearance - sample_spacing / 2); +inf without obstacles
  bool inside = true;             // every point inside the tissue and the path not longer than max_depth
  bool clear() const { return margin >= 0.0 && inside; }
};

struct SearchResult {
  bool feasible = false;
  CheckedPath best;                  // the plan chosen, or the closest approach when infeasible
  std::vector<CheckedPath> found;    // every feasible plan with the fewest rotations (best first)
  std::string reason;                // infeasible: why
  double seconds = 0.0;              // wall time of the search
  long paths = 0;                    // candidate paths traced and checked
  long partial = 0;                  // prefix poses solved for the last arc (no tracing)
  int rotations_searched = 0;        // the largest rotation count searched
};

// Checks one plan (its last arc cut where the path passes closest to the target).
CheckedPath checkPlan(const PlanProblem& pb, const Plan& plan);

SearchResult searchPlan(const PlanProblem& pb);

}  // namespace needlesim::planning
