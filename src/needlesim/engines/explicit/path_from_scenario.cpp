#include "needlesim/engines/explicit/path_from_scenario.hpp"

#include <cmath>
#include <fmt/format.h>

#include "needlesim/core/error.hpp"
#include "needlesim/engines/explicit/cohesive.hpp"
#include "needlesim/engines/explicit/path_needle.hpp"
#include "needlesim/engines/explicit/seam_path.hpp"
#include "needlesim/engines/explicit/solver.hpp"
#include "needlesim/engines/steering/kinematic.hpp"
#include "needlesim/engines/steering/steering_engines.hpp"

namespace needlesim::explicit_fe {

using Eigen::Vector2d;

ScenarioPath needleAxisPath(const Scenario& sc, double ds) {
  const auto& cs = sc.model.explicit_fe.cohesive;
  const double y0 = sc.insertion.entry_offset;
  ScenarioPath out;
  if (cs.path == "straight") return out;
  if (cs.path == "points") {
    for (const auto& p : cs.path_points) out.points.emplace_back(p.x, y0 + p.y);
    out.note = fmt::format("Crack path and needle: the {} user points of model.explicit.cohesive.path_points "
                           "(follow-the-leader needle, docs/models/cohesive.md \"Crack path\").",
                           cs.path_points.size());
    return out;
  }
  if (cs.path == "arc") {
    const double R = std::abs(cs.path_radius), sgn = cs.path_radius >= 0 ? 1.0 : -1.0;
    const double turn = std::min(M_PI / 4, sc.tissue.length / R);  // up to 45 deg, then straight
    const int n = std::max(2, static_cast<int>(std::ceil(R * turn / ds)));
    for (int k = 0; k <= n; ++k) {
      const double phi = turn * k / n;
      out.points.emplace_back(R * std::sin(phi), y0 + sgn * R * (1 - std::cos(phi)));
    }
    out.note = fmt::format("Crack path and needle: circular arc of radius {:g} mm curving towards {}y "
                           "(follow-the-leader needle, docs/models/cohesive.md \"Crack path\").",
                           R * 1e3, sgn > 0 ? "+" : "-");
    return out;
  }
  // steering: the kinematic model of seed 002 / Webster et al. with the steering inputs of this scenario
  const engines::SteeringInputs in = engines::steeringInputs(sc);
  const double kappa = sc.model.steering.curvature >= 0 ? sc.model.steering.curvature : -in.kappa_bof;
  if (!std::isfinite(kappa))
    throw Error("model.explicit.cohesive.path: steering needs a curvature: set model.steering.curvature or "
                "needle.youngs_modulus (for the beam-on-foundation curvature of the tip loads)");
  steering::KinematicParams par{kappa, ds};
  steering::Pose start;
  start.p = steering::Vec3(0, 0, in.start);
  std::vector<steering::Vec3> path(steering::kinematicSampleCount(par, in.plan));
  path.resize(steering::simulateKinematic(par, start, in.plan, path));
  if (in.start > 0) path.insert(path.begin(), steering::Vec3::Zero());
  for (const auto& p : path) {
    if (std::abs(p.x()) > 1e-9)
      throw Error("model.explicit.cohesive.path: the steering path leaves the insertion plane (spinning or a "
                  "bevel rotation other than 180 deg); a 2D path needs a fixed bevel");
    // steering entry frame: z along the insertion axis, y in the insertion plane (bevel orientation 0
    // steers towards -y, the sharp side, which is -y here too: bevelSide = +y at orientation 0)
    if (out.points.empty() || p.z() > out.points.back().x() + 1e-12) out.points.emplace_back(p.z(), y0 + p.y());
  }
  if (out.points.size() < 2) throw Error("model.explicit.cohesive.path: the steering path has fewer than 2 points");
  out.note = fmt::format("Crack path and needle: the tip path predicted before the run by the kinematic bevel-tip "
                         "model (seed 002, Webster et al. 2006), curvature {:.4g} 1/m towards the bevel's sharp "
                         "side{}; one-way coupling, the mesh is not re-meshed during the run (docs/models/cohesive.md).",
                         kappa, sc.model.steering.curvature >= 0 ? " (model.steering.curvature)"
                                                                : " (beam on a foundation, from the tip loads)");
  return out;
}

double CrackPathSetup::seamHeight(double x, double seamY) const { return seam.empty() ? seamY : pathHeight(seam, x); }

CrackPathSetup setupCrackPath(const Scenario& sc, const needle::NeedleShape& shape, double seamY, int bevelSign,
                              bool cohesiveSeam, Mesh& mesh) {
  const auto& ex = sc.model.explicit_fe;
  CrackPathSetup cp;
  const ScenarioPath axis = needleAxisPath(sc, 0.25 * ex.element_size);
  if (axis.points.empty()) return cp;
  if (!cohesiveSeam || mesh.dim != 2)
    throw Error("model.explicit.cohesive.path needs the 2d cohesive seam of a generated quad4 mesh");
  const double before = shape.length + std::max(0.0, -sc.insertion.start_depth) + 1e-3;
  cp.path = std::make_shared<NeedlePath>(axis.points, before, 2 * sc.tissue.length + 1e-3, 0.25 * ex.element_size);
  cp.side = bevelSign >= 0 ? 1 : -1;
  cp.seam = cp.path->offset(-shape.radius * cp.side);
  cp.note = axis.note;
  const double room = 0.5 * sc.tissue.width - std::abs(seamY);  // to the nearer lateral face
  const double plateau = std::min(0.5 * ex.core_width, 0.5 * room);
  try {
    morphOntoPath(mesh, seamY, cp.seam, plateau + 0.9 * (room - plateau), plateau);
  } catch (const Error& e) {
    throw Error(std::string("model.explicit.cohesive.path: ") + e.what() +
                "; use a gentler path, a wider block or a narrower core_width");
  }
  return cp;
}

void reportCrackPath(ResultSink& sink, const CrackPathSetup& cp, const RigidNeedle& n, const CohesiveInterface& c,
                     const std::vector<double>& X, const std::vector<double>& u, double h) {
  if (!cp.path) return;
  sink.note(cp.note);
  // the tissue opened along the path: lips behind the heel (and two elements), from 0.5 mm in
  const double heel = n.shape.tip == TipType::Bevel ? 2 * n.shape.radius / std::tan(n.shape.tipAngle) : 0.0;
  const auto lo = pathLipOffsets(n, c, X, u, 0.5e-3, n.station - heel - 2 * h);
  sink.result("path_lip_pairs", lo.pairs, "1", "seam pairs behind the needle's heel (from 0.5 mm) whose lips are measured");
  sink.result("path_lip_offset_wall_side", lo.meanA, "m",
              "mean offset of the wall-side lips from the needle's axis path along the local bevel side (-R: open)");
  sink.result("path_lip_offset_bevel_side", lo.meanB, "m",
              "mean offset of the bevel-side lips from the axis path along the local bevel side (+R: open)");
  sink.result("path_lip_offset_wall_side_max", lo.pairs ? lo.maxA : 0.0, "m",
              "largest wall-side lip offset (< 0: every lip on its side)");
  sink.result("path_lip_offset_bevel_side_min", lo.pairs ? lo.minB : 0.0, "m",
              "smallest bevel-side lip offset (> 0: every lip on its side)");
}

}  // namespace needlesim::explicit_fe
