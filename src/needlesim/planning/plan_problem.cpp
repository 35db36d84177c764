// The planning problem of a scenario and the kinematic model's paths (plan_problem.hpp).
#include "needlesim/planning/plan_problem.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "needlesim/core/error.hpp"
#include "needlesim/engines/steering/steering_engines.hpp"
#include "needlesim/needle/insertion_frame.hpp"
#include "needlesim/planning/channel.hpp"
#include "needlesim/scenario/scenario.hpp"

namespace needlesim::planning {
namespace {

constexpr double pi = std::numbers::pi;

Mat3 rotZ(double a) {
  const double c = std::cos(a), s = std::sin(a);
  Mat3 r;
  r << c, -s, 0, s, c, 0, 0, 0, 1;
  return r;
}

// The curvature engine kinematic would use (engines/steering/steering_engines.cpp, runKinematic).
double curvatureOf(const Scenario& sc) {
  if (sc.model.steering.curvature >= 0) return sc.model.steering.curvature;
  if (sc.needle.tip != TipType::Bevel) return 0.0;
  return -engines::steeringInputs(sc).kappa_bof;
}

std::vector<Obstacle> obstaclesOf(const Scenario& sc) {
  std::vector<Obstacle> out;
  for (const PlanAvoidSpec& a : sc.plan.avoid)
    for (const InclusionSpec& I : sc.tissue.inclusions)
      if (I.name == a.inclusion)
        out.push_back({I.name, I.shape == InclusionSpec::Shape::Cylinder, Vec3(I.x, I.y, I.z), I.radius, a.clearance});
  return out;
}

}  // namespace

double Obstacle::distance(const Vec3& p) const {
  if (cylinder) return std::hypot(p.x() - centre.x(), p.y() - centre.y()) - radius;
  return (p - centre).norm() - radius;
}

double Plan::length() const {
  double s = 0.0;
  for (const Arc& a : arcs) s += a.length - a.retract;
  return s;
}

int Plan::retractions() const {
  return static_cast<int>(std::count_if(arcs.begin(), arcs.end(), [](const Arc& a) { return a.retract > 0.0; }));
}

int Plan::rotations() const {
  int n = 0;
  for (std::size_t i = 1; i < arcs.size(); ++i)
    if (std::abs(std::remainder(arcs[i].rotate, 2 * pi)) > 1e-9) ++n;
  return n;
}

PlanProblem planProblem(const Scenario& sc) {
  const PlanSpec& p = sc.plan;
  if (!p.given)
    throw InputError(SourceLocation{sc.source, 0, 0}, "plan", "", "the scenario has no plan section",
                     "a plan section with a target (docs/planning.md)");
  PlanProblem pb;
  pb.kappa = curvatureOf(sc);
  pb.plan_kappa = pb.kappa * (1.0 - p.curvature_reserve);
  pb.duty_cycling = p.duty_cycling;
  pb.target = Vec3(p.target_depth, p.target_lateral, p.target_elevation);
  pb.tolerance = p.tolerance;
  pb.obstacles = obstaclesOf(sc);
  pb.needle_radius = sc.needle.outer_diameter / 2;
  const double half = sc.tissue.width / 2, off = sc.insertion.entry_offset;
  pb.offset_lo = std::max(-half, off - p.entry_window);
  pb.offset_hi = std::min(half, off + p.entry_window);
  pb.angle_lo = std::max(1e-3, sc.insertion.entry_angle - p.max_entry_angle);
  pb.angle_hi = std::min(pi - 1e-3, sc.insertion.entry_angle + p.max_entry_angle);
  pb.max_rotations = p.max_rotations;
  pb.max_retractions = p.max_retractions;
  pb.max_depth = p.max_depth;
  pb.lo = Vec3(0.0, -half, -sc.tissue.height / 2);
  pb.hi = Vec3(sc.tissue.length, half, sc.tissue.height / 2);
  pb.sample_spacing = p.sample_spacing;
  pb.max_paths = p.max_paths;
  pb.seed = static_cast<unsigned>(p.seed);
  pb.insertion = sc.insertion;
  return pb;
}

Pose entryPose(const PlanProblem& pb, double offset, double angle, double roll) {
  InsertionSpec in = pb.insertion;
  in.entry_offset = offset;
  in.entry_angle = angle;
  const needle::InsertionFrame f = needle::InsertionFrame::fromInsertion(in);
  Pose g;
  g.R.col(0) = -f.outOfPlane;
  g.R.col(1) = f.lateral;
  g.R.col(2) = f.axial;
  g.R = g.R * rotZ(roll);
  g.p = f.entry + Vec3(0.0, 0.0, pb.entry_elevation);
  return g;
}

Pose arcEnd(const Pose& from, const Arc& arc, double curvature_scale) {
  Pose g = from;
  if (arc.rotate != 0.0) g.R = g.R * rotZ(arc.rotate);
  const Pose step = steering::twistExp(Vec3(arc.curvature * curvature_scale, 0.0, 0.0), arc.length);
  g.p += g.R * step.p;
  g.R = g.R * step.R;
  return g;
}

double rollTowards(const Pose& pose, const Vec3& b) {
  // bevel direction after rotZ(psi): -R (-sin psi, cos psi, 0)
  const Vec3 local = pose.R.transpose() * b;
  return std::atan2(local.x(), -local.y());
}

Pose traceArc(Pose g, const Arc& a, double spacing, std::vector<Vec3>& out, double curvature_scale) {
  if (a.rotate != 0.0) g.R = g.R * rotZ(a.rotate);
  if (a.length <= 0) return g;
  const int n = std::max(1, static_cast<int>(std::ceil(a.length / spacing - 1e-9)));
  const Pose step = steering::twistExp(Vec3(a.curvature * curvature_scale, 0.0, 0.0), a.length / n);
  for (int i = 0; i < n; ++i) {
    g.p += g.R * step.p;
    g.R = g.R * step.R;
    out.push_back(g.p);
  }
  return g;
}

Pose tracePath(const Pose& start, const std::vector<Arc>& arcs, double spacing, std::vector<Vec3>& out,
               double curvature_scale) {
  out.push_back(start.p);
  if (std::any_of(arcs.begin(), arcs.end(), [](const Arc& a) { return a.retract > 0.0; })) {
    Channel channel(start, curvature_scale);
    for (const Arc& a : arcs) channel.follow(a, spacing, &out);
    return channel.tip();
  }
  Pose g = start;
  for (const Arc& a : arcs) g = traceArc(g, a, spacing, out, curvature_scale);
  return g;
}

}  // namespace needlesim::planning
