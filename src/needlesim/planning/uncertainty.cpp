// Monte Carlo of the targeting error (uncertainty.hpp).
#include "needlesim/planning/uncertainty.hpp"

#include "needlesim/planning/tip_estimator.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>

#include <Eigen/Geometry>

namespace needlesim::planning {
namespace {

constexpr double pi = std::numbers::pi;

// The curvature factor: the curvature's own spread, and the modulus's through the beam on an
// elastic foundation, whose steady curvature (M + Q/lambda)/EI with lambda = (K_T/4EI)^(1/4)
// goes as K_T^(-1/4) for the roller tip load (seed 002 section 4; docs/models/steering.md).
Draw drawOne(std::mt19937_64& rng, const PlanUncertaintySpec& u) {
  std::normal_distribution<double> n(0.0, 1.0);
  Draw d;
  const double curv = std::max(0.0, 1.0 + u.curvature_sd * n(rng));
  const double modulus = std::max(0.05, 1.0 + u.modulus_sd * n(rng));
  d.curvature_scale = curv * std::pow(modulus, -0.25);
  d.entry_shift = Vec3(0.0, u.entry_sd * n(rng), u.entry_sd * n(rng));
  d.tilt_y = u.angle_sd * n(rng);
  d.tilt_z = u.angle_sd * n(rng);
  d.target_shift = Vec3(u.target_sd * n(rng), u.target_sd * n(rng), u.target_sd * n(rng));
  return d;
}

Pose drawnStart(const PlanProblem& pb, const Plan& plan, const Draw& d) {
  Pose g = entryPose(pb, plan.entry_offset, plan.entry_angle, plan.roll);
  g.p += d.entry_shift;
  const Mat3 tilt = (Eigen::AngleAxisd(d.tilt_y, Vec3::UnitY()) * Eigen::AngleAxisd(d.tilt_z, Vec3::UnitZ())).matrix();
  g.R = tilt * g.R;
  return g;
}

bool touches(const PlanProblem& pb, const std::vector<Vec3>& points) {
  for (const Vec3& p : points)
    for (const Obstacle& o : pb.obstacles)
      if (o.distance(p) < pb.needle_radius) return true;
  return false;
}

void summarise(ErrorDistribution& e) {
  e.p50 = quantile(e.errors, 0.5);
  e.p95 = quantile(e.errors, 0.95);
  long t = 0;
  for (char c : e.touched) t += c;
  e.touch_probability = e.touched.empty() ? 0.0 : static_cast<double>(t) / static_cast<double>(e.touched.size());
}

// One segment of the closed loop, the bevel turned towards `towards` over the first
// (1 + f)/2 of it and away over the rest, f = needed/kappa: the average curvature is the needed
// one with the needle's own (bevel flips); duty-cycled, one arc at the needed curvature.
std::vector<Arc> correction(const PlanProblem& pb, double rotate, double needed, double seg, int& rotations) {
  if (pb.duty_cycling || pb.kappa <= 0) {
    rotations += rotate != 0.0;
    return {Arc{rotate, seg, std::min(needed, pb.kappa)}};
  }
  const double f = std::clamp(needed / pb.kappa, 0.0, 1.0);
  const double first = seg * (1 + f) / 2;
  rotations += (rotate != 0.0) + (seg - first > 0);
  if (seg - first <= 0) return {Arc{rotate, seg, pb.kappa}};
  return {Arc{rotate, first, pb.kappa}, Arc{pi, seg - first, pb.kappa}};
}

// One closed-loop insertion: the tip measured at the entry, after each arc before the last and
// every measure_every after; the target measured with each (its estimate: their mean); the
// needle's state estimated from all tip measurements (tip_estimator.hpp) and the last arc
// replanned from it.
double closedLoopOnce(const PlanProblem& pb, const Plan& plan, const PlanUncertaintySpec& u, std::mt19937_64& rng,
                      const Draw& d, std::vector<Vec3>& points, int& rotations) {
  std::normal_distribution<double> n(0.0, 1.0);
  const auto noise = [&]() -> Vec3 { return Vec3(n(rng), n(rng), n(rng)) * u.measurement_noise; };
  Pose truth = drawnStart(pb, plan, d);
  const double scale_sd = std::hypot(u.curvature_sd, u.modulus_sd / 4);
  TipEstimator est(entryPose(pb, plan.entry_offset, plan.entry_angle, plan.roll),
                   {0.0, u.entry_sd, u.entry_sd, u.angle_sd, u.angle_sd, u.angle_sd, scale_sd}, u.measurement_noise);
  const auto execute = [&](const Arc& a) {
    truth = tracePath(truth, {a}, pb.sample_spacing, points, d.curvature_scale);
    est.executed(a);
  };
  est.measured(truth.p + noise());
  for (std::size_t i = 0; i + 1 < plan.arcs.size(); ++i) {
    execute(plan.arcs[i]);
    est.measured(truth.p + noise());
  }
  rotations = plan.rotations();
  const Vec3 target = pb.target + d.target_shift;
  Vec3 target_sum = Vec3::Zero();
  double inserted = plan.length() - plan.arcs.back().length;
  for (int step = 1; step < 10000; ++step) {
    target_sum += target + noise();
    const Vec3 seen = target_sum / step;
    const Pose belief = est.pose();
    const Vec3 dv = seen - belief.p, t = belief.R.col(2);
    const Vec3 perp = dv - dv.dot(t) * t;
    if (dv.dot(t) <= 0) break;
    const double q = perp.norm(), needed = 2 * q / dv.squaredNorm();
    const double rotate = q > 0 ? rollTowards(belief, perp / q) : 0.0;
    const double remaining = needed > 0 ? 2 * std::atan2(q, dv.dot(t)) / needed : dv.norm();
    double seg = std::min(u.measure_every, remaining);
    if (remaining - seg < 0.25 * u.measure_every) seg = remaining;
    seg = std::min(seg, pb.max_depth - inserted);
    if (seg <= 0) break;
    for (const Arc& a : correction(pb, rotate, needed / est.curvatureScale(), seg, rotations)) execute(a);
    inserted += seg;
    if (seg >= remaining) break;
    est.measured(truth.p + noise());
  }
  return (truth.p - target).norm();
}

}  // namespace

double quantile(std::vector<double> v, double q) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const double at = q * static_cast<double>(v.size() - 1);
  const std::size_t i = static_cast<std::size_t>(std::floor(at));
  const double f = at - static_cast<double>(i);
  return i + 1 < v.size() ? v[i] * (1 - f) + v[i + 1] * f : v[i];
}

ErrorDistribution openLoopErrors(const PlanProblem& pb, const Plan& plan, const PlanUncertaintySpec& u) {
  ErrorDistribution e;
  std::mt19937_64 rng(static_cast<unsigned>(u.seed));
  std::vector<Vec3> points;
  for (int i = 0; i < u.samples; ++i) {
    const Draw d = drawOne(rng, u);
    points.clear();
    const Pose end = tracePath(drawnStart(pb, plan, d), plan.arcs, pb.sample_spacing, points, d.curvature_scale);
    e.errors.push_back((end.p - pb.target - d.target_shift).norm());
    e.touched.push_back(touches(pb, points));
  }
  e.mean_rotations = plan.rotations();
  summarise(e);
  return e;
}

ErrorDistribution closedLoopErrors(const PlanProblem& pb, const Plan& plan, const PlanUncertaintySpec& u) {
  ErrorDistribution e;
  std::mt19937_64 rng(static_cast<unsigned>(u.seed) + 1);
  std::vector<Vec3> points;
  double rotations = 0.0;
  for (int i = 0; i < u.samples; ++i) {
    const Draw d = drawOne(rng, u);
    points.clear();
    int r = 0;
    e.errors.push_back(closedLoopOnce(pb, plan, u, rng, d, points, r));
    e.touched.push_back(touches(pb, points));
    rotations += r;
  }
  e.mean_rotations = u.samples > 0 ? rotations / u.samples : 0.0;
  summarise(e);
  return e;
}

}  // namespace needlesim::planning
