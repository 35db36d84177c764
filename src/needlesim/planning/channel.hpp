#pragma once
// The channel a needle cuts in the kinematic bevel-tip model: the arcs the tip has followed,
// each from the pose where it began, so that the tip can be pulled back along them
// (a retraction) and steered into a new branch from there. The needle is rigid in torsion: an
// axial rotation turns the whole needle, so the tip pulled back to a depth has the channel's
// frame there turned by every rotation made since the tip passed it.
#include <vector>

#include "needlesim/planning/plan_problem.hpp"

namespace needlesim::planning {

class Channel {
 public:
  explicit Channel(const Pose& start, double curvature_scale = 1.0);
  // Pulls the tip back by arc.retract, turns the bevel by arc.rotate, inserts arc.length;
  // appends the new tip positions to `points` every `spacing` or closer (not the start).
  void follow(const Arc& arc, double spacing = 0.0, std::vector<Vec3>* points = nullptr);
  const Pose& tip() const { return tip_; }
  double depth() const { return depth_; }
  // The tip pose were it pulled back to `depth` (0 <= depth <= depth()).
  Pose at(double depth) const;

 private:
  struct Piece {
    Pose from;          // before the arc's rotation
    double from_depth;  // m
    Arc arc;
  };
  void retractTo(double depth);
  double scale_;
  std::vector<Piece> pieces_;
  Pose end_;             // the channel's end, without the rotations made since the tip was pulled back
  double pending_ = 0.0;  // rad, rotations made since then
  Pose tip_;
  double depth_ = 0.0;
};

}  // namespace needlesim::planning
