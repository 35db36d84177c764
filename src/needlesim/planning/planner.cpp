// The sampling-based planner with an analytic last arc (planner.hpp, docs/planning.md).
#include "needlesim/planning/planner.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>

namespace needlesim::planning {
namespace {

constexpr double pi = std::numbers::pi;
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr int kGrid = 16;        // samples of the free scalar before the roots are refined
constexpr int kBisections = 40;  // halvings of a bracket: 1e-12 of it
constexpr std::size_t kKeep = 32;  // feasible plans collected before the search stops

// The single arc from a pose through the target: seed 002's constant-curvature arc (Webster et
// al. 2006) in the plane of the needle axis and the target, with the bevel turned into it.
// A circle tangent to the axis t at p through the target d away has curvature 2 |d_perp| / |d|^2
// and turns by 2 atan2(|d_perp|, d.t).
struct Connection {
  bool ahead = false;   // the target lies ahead of the tip (the arc turns by less than 180 deg)
  double rotate = 0.0;  // rad, bevel rotation that turns the bevel towards the target
  double needed = 0.0;  // 1/m, curvature of the arc through the target
  double length = 0.0;  // m, arc length to the target
};

Connection connect(const Pose& g, const Vec3& target) {
  Connection c;
  const Vec3 d = target - g.p, t = g.R.col(2);
  const double a = d.dot(t);
  const Vec3 perp = d - a * t;
  const double q = perp.norm(), dd = d.squaredNorm();
  c.ahead = a > 0.0;
  if (!c.ahead) return c;
  c.needed = 2.0 * q / dd;
  c.rotate = q > 1e-12 * std::sqrt(dd) ? rollTowards(g, perp / q) : 0.0;
  const double turn = 2.0 * std::atan2(q, a);
  c.length = c.needed > 0.0 ? turn / c.needed : std::sqrt(dd);
  return c;
}

// A prefix of a plan: the entry and the arcs before the last, one scalar of which is free.
struct Prefix {
  Plan plan;                 // entry and the arcs before the last
  bool free_angle = false;   // the free scalar is the entry angle (else the last prefix arc's length)
  double lo = 0.0, hi = 0.0; // its range
};

class Searcher {
 public:
  explicit Searcher(const PlanProblem& pb) : pb_(pb), rng_(pb.seed) {}
  SearchResult run();

 private:
  const PlanProblem& pb_;
  std::mt19937_64 rng_;
  SearchResult out_;
  bool have_closest_ = false;
  long reached_ = 0, blocked_ = 0, outside_ = 0;
  std::vector<long> blocked_by_;

  double uniform(double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng_); }
  Plan withScalar(const Prefix& p, double s) const;
  Pose poseAfter(const Plan& prefix) const;
  void consider(Plan plan, const Connection& c, double curvature);
  void solve(const Prefix& p);
  void closest(const Prefix& p, const std::array<double, kGrid>& s, int nearest);
  void searchOneArc();
  void searchArcs(int arcs, long budget);
  Prefix randomPrefix(int arcs);
  void record(const CheckedPath& cp);
  void finish();
};

Plan Searcher::withScalar(const Prefix& p, double s) const {
  Plan plan = p.plan;
  if (p.free_angle)
    plan.entry_angle = s;
  else
    plan.arcs.back().length = s;
  return plan;
}

Pose Searcher::poseAfter(const Plan& prefix) const {
  Pose g = entryPose(pb_, prefix.entry_offset, prefix.entry_angle, prefix.roll);
  for (const Arc& a : prefix.arcs) g = arcEnd(g, a);
  return g;
}

// The last arc after the prefix: turned towards the target, at `curvature`, one and a half
// times the length of the arc through it when the curvature is not the needed one (the check
// cuts it where it passes closest).
void Searcher::consider(Plan plan, const Connection& c, double curvature) {
  Arc last{c.rotate, c.length, curvature};
  if (std::abs(curvature - c.needed) > 1e-9 * std::max(1.0, pb_.kappa)) last.length *= 1.5;
  last.length = std::min(last.length, std::max(0.0, pb_.max_depth - plan.length()));
  if (plan.arcs.empty()) {  // the one arc's turn is the bevel's roll before entry
    plan.roll = std::remainder(plan.roll + last.rotate, 2 * pi);
    last.rotate = 0.0;
  }
  plan.arcs.push_back(last);
  record(checkPlan(pb_, plan));
}

void Searcher::record(const CheckedPath& cp) {
  ++out_.paths;
  const bool reaches = cp.miss <= pb_.tolerance;
  if (reaches) ++reached_;
  if (reaches && !cp.inside) ++outside_;
  if (reaches && cp.inside && cp.margin < 0) {
    ++blocked_;
    for (std::size_t k = 0; k < pb_.obstacles.size(); ++k)
      if (cp.distances[k] - pb_.obstacles[k].clearance - pb_.sample_spacing / 2 < 0) ++blocked_by_[k];
  }
  if (reaches && cp.clear()) {
    out_.found.push_back(cp);
    return;
  }
  // the closest approach: clear paths first, then the smallest miss
  const bool better = !have_closest_ || (cp.clear() && !out_.best.clear()) ||
                      (cp.clear() == out_.best.clear() && cp.miss < out_.best.miss);
  if (better) {
    out_.best = cp;
    have_closest_ = true;
  }
}

// Solves the free scalar of a prefix for the last arc: the roots of (needed - kappa) on a grid
// refined by bisection; duty-cycled, the grid point needing the most curvature up to kappa;
// with neither, the grid point nearest to a root (for the closest approach).
void Searcher::solve(const Prefix& p) {
  std::array<double, kGrid> s{}, g{};
  std::array<Connection, kGrid> c{};
  int duty = -1, nearest = -1;
  for (int i = 0; i < kGrid; ++i) {
    s[i] = kGrid == 1 ? p.lo : p.lo + (p.hi - p.lo) * i / (kGrid - 1);
    c[i] = connect(poseAfter(withScalar(p, s[i])), pb_.target);
    ++out_.partial;
    g[i] = c[i].ahead ? c[i].needed - pb_.plan_kappa : std::numeric_limits<double>::quiet_NaN();
    if (!c[i].ahead) continue;
    if (pb_.duty_cycling && g[i] <= 0 && (duty < 0 || g[i] > g[duty])) duty = i;
    if (nearest < 0 || std::abs(g[i]) < std::abs(g[nearest])) nearest = i;
  }
  bool any = false;
  for (int i = 0; i + 1 < kGrid; ++i) {
    if (!(g[i] * g[i + 1] <= 0) || (g[i] == 0 && i > 0)) continue;
    double a = s[i], b = s[i + 1], ga = g[i];
    for (int k = 0; k < kBisections && b - a > 1e-14; ++k) {
      const double m = 0.5 * (a + b);
      const Connection cm = connect(poseAfter(withScalar(p, m)), pb_.target);
      ++out_.partial;
      const double gm = cm.ahead ? cm.needed - pb_.plan_kappa : -ga;
      (gm * ga > 0 ? a : b) = m;
      if (gm * ga > 0) ga = gm;
    }
    const Plan plan = withScalar(p, 0.5 * (a + b));
    const Connection cr = connect(poseAfter(plan), pb_.target);
    if (cr.ahead) consider(plan, cr, pb_.plan_kappa), any = true;
  }
  if (duty >= 0) consider(withScalar(p, s[duty]), c[duty], c[duty].needed), any = true;
  if (!any && out_.found.empty() && nearest >= 0) closest(p, s, nearest);
}

// No root on the grid: |needed - kappa| minimised by golden sections between the neighbours of
// the grid point nearest to one (a straight needle aimed at a point, the closest approach).
void Searcher::closest(const Prefix& p, const std::array<double, kGrid>& s, int nearest) {
  double a = s[std::max(0, nearest - 1)], b = s[std::min(kGrid - 1, nearest + 1)];
  const double r = (std::sqrt(5.0) - 1) / 2;
  const auto cost = [&](double x) {
    const Connection c = connect(poseAfter(withScalar(p, x)), pb_.target);
    ++out_.partial;
    return c.ahead ? std::abs(c.needed - pb_.plan_kappa) : std::numeric_limits<double>::infinity();
  };
  double x1 = b - r * (b - a), x2 = a + r * (b - a), f1 = cost(x1), f2 = cost(x2);
  for (int k = 0; k < kBisections; ++k) {
    if (f1 < f2) b = x2, x2 = x1, f2 = f1, x1 = b - r * (b - a), f1 = cost(x1);
    else a = x1, x1 = x2, f1 = f2, x2 = a + r * (b - a), f2 = cost(x2);
  }
  const Plan plan = withScalar(p, 0.5 * (a + b));
  const Connection c = connect(poseAfter(plan), pb_.target);
  if (c.ahead) consider(plan, c, pb_.plan_kappa);
}

// No rotation: one arc from the entry, the entry angle solved for, over a grid of entry points
// (the scenario's own first).
void Searcher::searchOneArc() {
  const int n = pb_.offset_hi - pb_.offset_lo > 1e-9 ? 33 : 1;
  const double centre = std::clamp(pb_.insertion.entry_offset, pb_.offset_lo, pb_.offset_hi);
  for (int i = 0; i < n && out_.found.size() < kKeep && out_.paths < pb_.max_paths; ++i) {
    Prefix p;
    p.plan.entry_offset = i == 0 ? centre : pb_.offset_lo + (pb_.offset_hi - pb_.offset_lo) * (i - 1) / (n - 2);
    p.free_angle = true;
    p.lo = pb_.angle_lo;
    p.hi = pb_.angle_hi;
    if (p.hi - p.lo < 1e-12) {  // one direction: the grid collapses to it
      p.plan.entry_angle = p.lo;
      const Connection c = connect(poseAfter(p.plan), pb_.target);
      ++out_.partial;
      if (c.ahead) {
        const bool duty = pb_.duty_cycling && c.needed <= pb_.kappa;
        consider(p.plan, c, duty ? c.needed : pb_.plan_kappa);
      }
      continue;
    }
    solve(p);
  }
}

// `arcs` - 1 arcs before the last, at random: entry, roll, lengths and rotations; the length of
// the last of them is the free scalar.
Prefix Searcher::randomPrefix(int arcs) {
  Prefix p;
  p.plan.entry_offset = uniform(pb_.offset_lo, pb_.offset_hi + 1e-300);
  p.plan.entry_angle = uniform(pb_.angle_lo, pb_.angle_hi + 1e-300);
  p.plan.roll = uniform(-pi, pi);
  const double reach = std::min(pb_.max_depth, 1.2 * (pb_.target - entryPose(pb_, p.plan.entry_offset, p.plan.entry_angle, 0).p).norm());
  double used = 0.0;
  for (int k = 0; k + 1 < arcs; ++k) {
    Arc a{k == 0 ? 0.0 : uniform(-pi, pi), 0.0, pb_.plan_kappa};
    if (k + 2 < arcs) a.length = uniform(0.02, 0.9 / (arcs - 1)) * reach;
    used += a.length;
    p.plan.arcs.push_back(a);
  }
  p.lo = 0.0;
  p.hi = std::max(0.0, 0.95 * reach - used);
  return p;
}

void Searcher::searchArcs(int arcs, long budget) {
  const long stop = out_.paths + budget;
  // each prefix costs kGrid solves or more: at most budget / kGrid prefixes
  for (long it = 0; it < budget / kGrid + 1 && out_.paths < stop && out_.found.size() < kKeep; ++it) {
    const Prefix p = randomPrefix(arcs);
    if (p.hi > p.lo) solve(p);
  }
}

void Searcher::finish() {
  if (!out_.found.empty()) {
    std::stable_sort(out_.found.begin(), out_.found.end(), [](const CheckedPath& a, const CheckedPath& b) {
      return a.margin != b.margin ? a.margin > b.margin : a.miss < b.miss;
    });
    out_.feasible = true;
    out_.best = out_.found.front();
    return;
  }
  const std::string closest = fmt::format("closest approach {:.3g} mm", out_.best.miss * 1e3);
  if (reached_ == 0) {
    out_.reason = fmt::format("the target is beyond the reach of the needle's curvature ({:.4g} 1/m) from the entry "
                              "window with up to {} rotation(s) ({})", pb_.kappa, pb_.max_rotations, closest);
  } else if (blocked_ > 0) {
    const auto worst = std::max_element(blocked_by_.begin(), blocked_by_.end()) - blocked_by_.begin();
    const Obstacle& o = pb_.obstacles[worst];
    out_.reason = fmt::format("every path found that reaches the target passes closer to '{}' than its clearance "
                              "({:.3g} mm; {} of {} such paths); {} of a path that keeps the clearances",
                              o.name, o.clearance * 1e3, blocked_, reached_, closest);
  } else {
    out_.reason = fmt::format("every path found that reaches the target leaves the tissue or is longer than "
                              "max_depth ({:.4g} mm); {}", pb_.max_depth * 1e3, closest);
  }
}

SearchResult Searcher::run() {
  const auto t0 = std::chrono::steady_clock::now();
  blocked_by_.assign(pb_.obstacles.size(), 0);
  searchOneArc();
  out_.rotations_searched = 0;
  for (int arcs = 2; arcs <= pb_.max_rotations + 1 && out_.found.empty(); ++arcs) {
    const long left = pb_.max_paths - out_.paths;
    if (left <= 0) break;
    searchArcs(arcs, left / (pb_.max_rotations + 2 - arcs));
    out_.rotations_searched = arcs - 1;
  }
  finish();
  out_.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return out_;
}

}  // namespace

CheckedPath checkPlan(const PlanProblem& pb, const Plan& plan) {
  CheckedPath cp;
  cp.plan = plan;
  const double h = pb.sample_spacing;
  Pose g = entryPose(pb, plan.entry_offset, plan.entry_angle, plan.roll);
  std::vector<Arc> prefix(plan.arcs.begin(), plan.arcs.end() - (plan.arcs.empty() ? 0 : 1));
  g = tracePath(g, prefix, h, cp.points);
  if (!plan.arcs.empty()) {  // the last arc, cut where it passes closest to the target
    std::vector<Vec3> last;
    tracePath(g, {plan.arcs.back()}, h, last);
    std::size_t j = 0;
    for (std::size_t i = 1; i < last.size(); ++i)
      if ((last[i] - pb.target).squaredNorm() < (last[j] - pb.target).squaredNorm()) j = i;
    const double L = plan.arcs.back().length;
    const std::size_t n = last.size() - 1;
    cp.plan.arcs.back().length = n > 0 ? L * static_cast<double>(j) / static_cast<double>(n) : 0.0;
    cp.points.insert(cp.points.end(), last.begin() + 1, last.begin() + 1 + j);
  }
  cp.miss = (cp.points.back() - pb.target).norm();
  cp.margin = kInf;
  cp.distances.assign(pb.obstacles.size(), kInf);
  for (const Vec3& p : cp.points) {
    for (std::size_t k = 0; k < pb.obstacles.size(); ++k) cp.distances[k] = std::min(cp.distances[k], pb.obstacles[k].distance(p));
    for (int a = 0; a < 3; ++a)
      if (p[a] < pb.lo[a] - 1e-12 || p[a] > pb.hi[a] + 1e-12) cp.inside = false;
  }
  for (std::size_t k = 0; k < pb.obstacles.size(); ++k)
    cp.margin = std::min(cp.margin, cp.distances[k] - pb.obstacles[k].clearance - h / 2);
  if (cp.plan.length() > pb.max_depth * (1 + 1e-12)) cp.inside = false;
  return cp;
}

SearchResult searchPlan(const PlanProblem& pb) { return Searcher(pb).run(); }

}  // namespace needlesim::planning
