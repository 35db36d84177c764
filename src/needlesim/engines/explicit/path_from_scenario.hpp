#pragma once
// The needle-axis path of model.explicit.cohesive.path (docs/models/cohesive.md "Crack path"),
// in the block frame (x depth from the entry face, y across; the entry point at (0, entry_offset)):
//  straight: empty (the engine's straight needle and seam);
//  points:   the user's path_points (y relative to the straight line through the entry point);
//  arc:      a circular arc of radius |path_radius| tangent to the insertion axis at the entry point,
//            curving towards sign(path_radius) y, sampled every ds up to 45 deg of turn (then straight);
//  steering: the tip path the kinematic bevel-tip model (Webster et al. 2006, as used in seed 002
//            sections 1 and 5.1; engines/steering/kinematic.hpp) predicts for this scenario's needle,
//            tissue and insertion plan, with the curvature of model.steering.curvature or else the
//            beam-on-foundation steady curvature of the tip loads (steering_engines.hpp). Predicted
//            before the run (one-way coupling): the explicit run does not re-mesh.
#include <Eigen/Core>
#include <string>
#include <vector>

#include "needlesim/scenario/scenario.hpp"

namespace needlesim::explicit_fe {

struct ScenarioPath {
  std::vector<Eigen::Vector2d> points;  // empty = straight
  std::string note;                     // how it was made (for the run's notes)
};

// Throws Error with the field name when the path cannot be made (e.g. steering without curvature).
ScenarioPath needleAxisPath(const Scenario& sc, double ds);

}  // namespace needlesim::explicit_fe
