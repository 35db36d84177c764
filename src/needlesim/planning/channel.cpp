// The tip's channel, with retraction along it (channel.hpp).
#include "needlesim/planning/channel.hpp"

#include <algorithm>
#include <cmath>

namespace needlesim::planning {
namespace {

// The pose turned by `angle` about its axis (model z).
Pose turned(Pose g, double angle) {
  if (angle == 0.0) return g;
  const double c = std::cos(angle), s = std::sin(angle);
  Mat3 r;
  r << c, -s, 0, s, c, 0, 0, 0, 1;
  g.R = g.R * r;
  return g;
}

}  // namespace

Channel::Channel(const Pose& start, double curvature_scale) : scale_(curvature_scale), end_(start), tip_(start) {}

Pose Channel::at(double depth) const {
  if (depth >= depth_ || pieces_.empty()) return tip_;
  std::size_t k = pieces_.size() - 1;
  while (k > 0 && pieces_[k].from_depth > depth) --k;
  double later = pending_;
  for (std::size_t j = k + 1; j < pieces_.size(); ++j) later += pieces_[j].arc.rotate;
  const Piece& p = pieces_[k];
  const Pose g = arcEnd(p.from, Arc{p.arc.rotate, std::max(0.0, depth - p.from_depth), p.arc.curvature}, scale_);
  return turned(g, later);
}

void Channel::retractTo(double depth) {
  depth = std::clamp(depth, 0.0, depth_);
  if (depth >= depth_ || pieces_.empty()) return;
  tip_ = at(depth);
  std::size_t k = pieces_.size() - 1;
  while (k > 0 && pieces_[k].from_depth > depth) --k;
  for (std::size_t j = k + 1; j < pieces_.size(); ++j) pending_ += pieces_[j].arc.rotate;
  pieces_.resize(k + 1);
  Piece& p = pieces_[k];
  p.arc.length = std::max(0.0, depth - p.from_depth);
  end_ = arcEnd(p.from, p.arc, scale_);
  depth_ = depth;
}

void Channel::follow(const Arc& arc, double spacing, std::vector<Vec3>* points) {
  if (arc.retract > 0.0) retractTo(depth_ - arc.retract);
  const Arc a{pending_ + arc.rotate, std::max(0.0, arc.length), arc.curvature};
  pieces_.push_back(Piece{end_, depth_, a});
  pending_ = 0.0;
  Pose g = turned(end_, a.rotate);
  if (points && a.length > 0)
    g = traceArc(g, Arc{0.0, a.length, a.curvature}, spacing, *points, scale_);
  else if (a.length > 0)
    g = arcEnd(g, Arc{0.0, a.length, a.curvature}, scale_);
  end_ = tip_ = g;
  depth_ += a.length;
}

}  // namespace needlesim::planning
