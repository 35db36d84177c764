// Monte Carlo of the targeting error (uncertainty.hpp).
#include "needlesim/planning/uncertainty.hpp"

#include "needlesim/planning/channel.hpp"
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

// What one closed-loop insertion did.
struct Execution {
  double error = 0.0;                // m, tip to the displaced target at the end
  int rotations = 0;
  std::vector<double> retracted_to;  // m, the depth of each retraction
  Plan actions;                      // the entry and every arc executed, retractions included
};

// One closed-loop insertion: the tip measured at the entry, after each arc before the last and
// every measure_every after; the target measured with each (its estimate: their mean); the
// needle's state estimated from all tip measurements (tip_estimator.hpp) and the last arc
// replanned from it. Where the estimated tip can no longer reach the target (its closest
// approach with the whole curvature beyond the tolerance, checked before each segment and,
// measured, where the insertion ended) and retractions are left, the tip is pulled back along its channel to the deepest depth from which the target needs at most
// the planned share of the curvature (and at most kRetractShare of it), then steered anew.
class ClosedLoop {
 public:
  ClosedLoop(const PlanProblem& pb, const Plan& plan, const PlanUncertaintySpec& u, std::mt19937_64& rng, const Draw& d,
             std::vector<Vec3>& points)
      : pb_(pb), plan_(plan), u_(u), rng_(rng), d_(d), points_(points), truth_(drawnStart(pb, plan, d), d.curvature_scale),
        est_(entryPose(pb, plan.entry_offset, plan.entry_angle, plan.roll),
             {0.0, u.entry_sd, u.entry_sd, u.angle_sd, u.angle_sd, u.angle_sd, std::hypot(u.curvature_sd, u.modulus_sd / 4)},
             u.measurement_noise) {
    points_.push_back(truth_.tip().p);
    out_.actions = plan;
    out_.actions.arcs.clear();
  }
  Execution run();

 private:
  static constexpr double kRetractShare = 0.75;
  Vec3 noise() { return Vec3(n_(rng_), n_(rng_), n_(rng_)) * u_.measurement_noise; }
  void measure() { est_.measured(truth_.tip().p + noise()); }
  void execute(const Arc& a);
  double predictedMiss(const Vec3& seen) const;
  bool retract(const Vec3& seen);
  bool correct(const Vec3& seen);

  const PlanProblem& pb_;
  const Plan& plan_;
  const PlanUncertaintySpec& u_;
  std::mt19937_64& rng_;
  std::normal_distribution<double> n_{0.0, 1.0};
  const Draw& d_;
  std::vector<Vec3>& points_;
  Channel truth_;
  TipEstimator est_;
  Execution out_;
  double inserted_ = 0.0;  // m, the tip's depth along its channel
};

void ClosedLoop::execute(const Arc& a) {
  truth_.follow(a, pb_.sample_spacing, &points_);
  est_.executed(a);
  std::vector<Arc>& done = out_.actions.arcs;
  if (!done.empty() && done.back().length == 0.0 && done.back().retract > 0.0) {  // the arc after a retraction
    done.back().retract += a.retract;
    done.back().rotate += a.rotate;
    done.back().length = a.length;
    done.back().curvature = a.curvature;
  } else {
    done.push_back(a);
  }
}

// The estimated tip's closest approach to the target along the arc of the whole estimated
// curvature turned towards it (0 where that curvature reaches it).
double ClosedLoop::predictedMiss(const Vec3& seen) const {
  const Pose belief = est_.pose();
  const Vec3 dv = seen - belief.p, t = belief.R.col(2);
  const double ahead = dv.dot(t), q = (dv - ahead * t).norm();
  const double k = pb_.kappa * est_.curvatureScale();
  if (ahead <= 0) return dv.norm();  // passed: the tip does not go back by itself
  if (2 * q / dv.squaredNorm() <= k) return 0.0;
  if (k <= 0 || q == 0) return q;
  const Vec3 centre = belief.p + (dv - ahead * t) / (q * k);
  return std::abs((seen - centre).norm() - 1 / k);
}

// Searches the retraction depth, every sample_spacing back from the tip, and pulls the tip back.
bool ClosedLoop::retract(const Vec3& seen) {
  if (pb_.kappa <= 0) return false;  // a needle that does not curve gains nothing by a new branch
  const double reach = std::min(pb_.plan_kappa / pb_.kappa, kRetractShare) * pb_.kappa * est_.curvatureScale();
  for (double s = inserted_ - pb_.sample_spacing; s >= pb_.sample_spacing; s -= pb_.sample_spacing) {
    const Pose g = est_.poseAt(s);
    const Vec3 dv = seen - g.p, t = g.R.col(2);
    const double ahead = dv.dot(t);
    if (ahead <= 0 || 2 * (dv - ahead * t).norm() / dv.squaredNorm() > reach) continue;
    execute(Arc{0.0, 0.0, 0.0, inserted_ - s});
    inserted_ = s;
    out_.retracted_to.push_back(s);
    return true;
  }
  return false;
}

// One replanned segment towards the target; false when the insertion ends.
bool ClosedLoop::correct(const Vec3& seen) {
  const Pose belief = est_.pose();
  const Vec3 dv = seen - belief.p, t = belief.R.col(2);
  const Vec3 perp = dv - dv.dot(t) * t;
  if (dv.dot(t) <= 0) return false;
  const double q = perp.norm(), needed = 2 * q / dv.squaredNorm();
  const double rotate = q > 0 ? rollTowards(belief, perp / q) : 0.0;
  const double remaining = needed > 0 ? 2 * std::atan2(q, dv.dot(t)) / needed : dv.norm();
  double seg = std::min(u_.measure_every, remaining);
  if (remaining - seg < 0.25 * u_.measure_every) seg = remaining;
  seg = std::min(seg, pb_.max_depth - inserted_);
  if (seg <= 0) return false;
  for (const Arc& a : correction(pb_, rotate, needed / est_.curvatureScale(), seg, out_.rotations)) execute(a);
  inserted_ += seg;
  if (seg >= remaining) return false;
  measure();
  return true;
}

Execution ClosedLoop::run() {
  measure();
  for (std::size_t i = 0; i + 1 < plan_.arcs.size(); ++i) {
    execute(plan_.arcs[i]);
    measure();
  }
  out_.rotations = plan_.rotations();
  const Vec3 target = pb_.target + d_.target_shift;
  Vec3 target_sum = Vec3::Zero();
  inserted_ = plan_.length() - plan_.arcs.back().length;
  bool ended = false;  // the insertion ended and the tip was measured there
  for (int step = 1; step < 10000; ++step) {
    target_sum += target + noise();
    const Vec3 seen = target_sum / step;
    const bool may_retract = static_cast<int>(out_.retracted_to.size()) < pb_.max_retractions;
    if (may_retract && predictedMiss(seen) > pb_.tolerance && retract(seen)) {
      measure();
      ended = false;
      continue;
    }
    if (!ended && correct(seen)) continue;
    if (ended || !may_retract) break;
    measure();
    ended = true;
  }
  out_.error = (truth_.tip().p - target).norm();
  return out_;
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
  double rotations = 0.0, retracted_to = 0.0;
  long retractions = 0, retracting = 0;
  for (int i = 0; i < u.samples; ++i) {
    const Draw d = drawOne(rng, u);
    std::mt19937_64 noise(rng());  // each sample's own measurement noise: samples compare across settings
    points.clear();
    const Execution x = ClosedLoop(pb, plan, u, noise, d, points).run();
    e.errors.push_back(x.error);
    e.touched.push_back(touches(pb, points));
    rotations += x.rotations;
    e.retractions.push_back(static_cast<int>(x.retracted_to.size()));
    e.retracted_to.push_back(x.retracted_to.empty() ? 0.0 : x.retracted_to.front());
    for (double s : x.retracted_to) retracted_to += s;
    retractions += static_cast<long>(x.retracted_to.size());
    if (!x.retracted_to.empty() && retracting++ == 0) e.retracting_example = x.actions;
  }
  e.mean_rotations = u.samples > 0 ? rotations / u.samples : 0.0;
  e.mean_retractions = u.samples > 0 ? static_cast<double>(retractions) / u.samples : 0.0;
  e.retracting_share = u.samples > 0 ? static_cast<double>(retracting) / u.samples : 0.0;
  e.mean_retracted_to = retractions > 0 ? retracted_to / static_cast<double>(retractions) : 0.0;
  summarise(e);
  return e;
}

}  // namespace needlesim::planning
