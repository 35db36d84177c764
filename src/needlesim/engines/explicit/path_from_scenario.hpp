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
#include <memory>
#include <string>
#include <vector>

#include "needlesim/engines/engine.hpp"
#include "needlesim/engines/explicit/mesh.hpp"
#include "needlesim/needle/surface_mesh.hpp"
#include "needlesim/scenario/scenario.hpp"

namespace needlesim::explicit_fe {

struct ScenarioPath {
  std::vector<Eigen::Vector2d> points;  // empty = straight
  std::string note;                     // how it was made (for the run's notes)
};

// Throws Error with the field name when the path cannot be made (e.g. steering without curvature).
ScenarioPath needleAxisPath(const Scenario& sc, double ds);

class NeedlePath;
class CohesiveInterface;
struct RigidNeedle;

// The engine's crack path set-up (explicit_engine.cpp): the needle path (resampled every h/4, extended
// straight behind the entry by the needle length and beyond the block), and the 2D mesh's split seam line
// y = seamY morphed onto the path offset by -R bevelSide (seam_path.hpp), with the refined core
// (core_width / 2 each side) moved rigidly and the weight falling to 0 at 90 % of the way to the nearer
// lateral face. Straight: nothing is done (path null).
struct CrackPathSetup {
  std::shared_ptr<const NeedlePath> path;  // null = the straight needle
  std::vector<Eigen::Vector2d> seam;       // the seam line through the sharp point (empty = y = seamY)
  int side = 1;                            // bevelSide = side x the path normal
  std::string note;
  double seamHeight(double x, double seamY) const;
};
CrackPathSetup setupCrackPath(const Scenario& sc, const needle::NeedleShape& shape, double seamY, int bevelSign,
                              bool cohesiveSeam, Mesh& mesh);
// Summary results of a path run: where the lips lie across the path behind the heel (path_needle.hpp).
void reportCrackPath(ResultSink& sink, const CrackPathSetup& cp, const RigidNeedle& n, const CohesiveInterface& c,
                     const std::vector<double>& X, const std::vector<double>& u, double elementSize);

}  // namespace needlesim::explicit_fe
