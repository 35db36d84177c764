#include "needlesim/engines/mpm/mpm_outputs.hpp"

#include "needlesim/engines/mpm/marker_errors.hpp"
#include "needlesim/needle/surface_mesh.hpp"
#include "needlesim/tissue/regions.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <limits>
#include <map>
#include <unordered_map>

namespace needlesim::engines::mpm_outputs {

using mpm::Mat3;

namespace {

double vonMises(const Mat3& s) {
  const double a = s(0, 0), b = s(1, 1), c = s(2, 2);
  return std::sqrt(0.5 * ((a - b) * (a - b) + (b - c) * (b - c) + (c - a) * (c - a)) +
                   3.0 * (s(0, 1) * s(0, 1) + s(1, 2) * s(1, 2) + s(0, 2) * s(0, 2)));
}

constexpr double kSeparation = 1.5;  // grid cells (FractureTracker)

// The surface of the solver's needle as placed: solid, of its radius, length and tip.
needle::SurfaceMesh needleSurfaceOf(const mpm::RigidBody& n) {
  needle::NeedleShape shape;
  shape.radius = n.radius;
  shape.length = n.length;
  shape.tipAngle = n.tipAngle;
  shape.tip = n.tip == mpm::RigidBody::Tip::Bevel     ? TipType::Bevel
              : n.tip == mpm::RigidBody::Tip::Conical ? TipType::Conical
                                                      : TipType::Blunt;
  const needle::NeedlePose pose{n.axisPoint(), n.axis, n.bevelSide};
  return needle::needleSurface3D(shape, pose, 24, 4);
}

}  // namespace

// ---------------------------------------------------------------- markers

MarkerSet::MarkerSet(const std::vector<MpmMarkerSpec>& specs, const MpmSolver& solver, const Vec3& entry) {
  std::vector<io::Column> cols{{"time", "s"}, {"depth", "m"}};
  for (const auto& mk : specs) {
    const Vec3 want = entry + Vec3(mk.x, mk.y, mk.z);
    Marker m;
    m.name = mk.name;
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t p = 0; p < solver.size(); ++p) {
      const double d = (solver.position(p) - want).squaredNorm();
      if (d < best) {
        best = d;
        m.particle = p;
      }
    }
    m.x0 = solver.position(m.particle);
    farthest_ = std::max(farthest_, (m.x0 - want).norm());
    markers_.push_back(m);
    for (const char* k : {"_ux", "_uy", "_uz", "_uxy"}) cols.push_back({m.name + k, "m"});
  }
  table_ = io::Table(cols);
}

void MarkerSet::record(const MpmSolver& solver, double t, double depth) {
  if (markers_.empty()) return;
  std::vector<double> row{t, depth};
  for (auto& m : markers_) {
    const Vec3 u = solver.position(m.particle) - m.x0;
    const double uxy = std::hypot(u.x(), u.y());  // eq 36
    m.maxUxy = std::max(m.maxUxy, uxy);
    row.insert(row.end(), {u.x(), u.y(), u.z(), uxy});
  }
  table_.addRow(row);
}

std::vector<double> MarkerSet::largest() const {
  std::vector<double> v;
  for (const auto& m : markers_) v.push_back(m.maxUxy);
  return v;
}

void MarkerSet::setLargest(const std::vector<double>& uxy) {
  for (std::size_t i = 0; i < markers_.size(); ++i) markers_[i].maxUxy = uxy[i];
}

std::vector<std::string> MarkerSet::names() const {
  std::vector<std::string> v;
  for (const auto& m : markers_) v.push_back(m.name);
  return v;
}

void MarkerSet::results(const MpmSolver& solver, ResultSink& sink) const {
  if (markers_.empty()) return;
  for (const auto& m : markers_) {
    const Vec3 u = solver.position(m.particle) - m.x0;
    sink.result("marker_" + m.name + "_uxy_final", std::hypot(u.x(), u.y()), "m",
                "final in-plane displacement of marker " + m.name + " (eq 36)");
    sink.result("marker_" + m.name + "_uxy_max", m.maxUxy, "m",
                "largest recorded in-plane displacement of marker " + m.name + " (eq 36)");
  }
  sink.note(fmt::format("Markers follow the material point nearest to each given position (at most {:.3g} mm away).",
                        farthest_ * 1e3));
}

// ---------------------------------------------------------------- numerical fracture

void FractureTracker::init(const MpmSolver& s, const Vec3& entry, const Vec3& axis) {
  const std::size_t np = s.size();
  const double dp = s.particleSpacing(), reach = 1.05 * dp;
  auto key = [&](const Vec3& x) {
    const auto c = [&](int d) { return static_cast<std::int64_t>(std::floor(x[d] / dp)) & 0x1fffff; };
    return (c(0) << 42) | (c(1) << 21) | c(2);
  };
  std::unordered_map<std::int64_t, std::vector<std::uint32_t>> cells;
  cells.reserve(np);
  for (std::size_t p = 0; p < np; ++p) cells[key(s.position(p))].push_back(static_cast<std::uint32_t>(p));
  auto addPair = [&](std::size_t p, std::uint32_t q) {
    a.push_back(static_cast<std::uint32_t>(p));
    b.push_back(q);
    const Vec3 m = 0.5 * (s.position(p) + s.position(q)) - entry;
    const double along = m.dot(axis);
    pathDepth.push_back(along);
    radial.push_back((m - along * axis).norm());
  };
  for (std::size_t p = 0; p < np; ++p) {
    const Vec3 x = s.position(p);
    for (int i = -1; i <= 1; ++i)
      for (int j = -1; j <= 1; ++j)
        for (int k = -1; k <= 1; ++k) {
          const auto it = cells.find(key(x + dp * Vec3(i, j, k)));
          if (it == cells.end()) continue;
          for (const std::uint32_t q : it->second)
            if (q > p && (s.position(q) - x).norm() <= reach) addPair(p, q);
        }
  }
  separated.assign(a.size(), 0);
}

void FractureTracker::check(const MpmSolver& s, double t, double tipDepth) {
  const mpm::MpmConfig& c = s.config();
  const double h = c.h, lim2 = kSeparation * kSeparation * h * h;
  std::map<long, std::pair<double, int>> bins;  // bin -> (sum of path depths, count)
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (separated[i]) continue;
    const Vec3 xa = s.position(a[i]), xb = s.position(b[i]);
    bool sep = (xa - xb).squaredNorm() > lim2;
    for (int d = 0; d < 3 && !sep; ++d)
      sep = std::abs(std::floor((xa[d] - c.origin[d]) / h) - std::floor((xb[d] - c.origin[d]) / h)) > 1.5;
    if (!sep) continue;
    separated[i] = 1;
    ++total;
    if (std::isnan(onsetDepth)) {
      onsetDepth = tipDepth;
      onsetTime = t;
    }
    if (std::isnan(deepest) || pathDepth[i] > deepest) deepest = pathDepth[i];
    widest = std::max(widest, radial[i]);
    auto& bin = bins[static_cast<long>(std::floor(pathDepth[i] / h))];
    bin.first += pathDepth[i];
    ++bin.second;
  }
  for (const auto& [k, v] : bins)
    table.addRow({t, tipDepth, v.first / v.second, static_cast<double>(v.second), static_cast<double>(total)});
}

void FractureTracker::results(ResultSink& sink) const {
  sink.result("fracture_pairs", static_cast<double>(total), "1",
              "neighbouring material-point pairs separated into non-adjacent cells or > 1.5 cells apart "
              "(numerical fracture, section 3.4)");
  if (total == 0) return;
  sink.result("fracture_onset_depth", onsetDepth, "m", "tip depth when the first pair separated");
  sink.result("fracture_onset_time", onsetTime, "s", "time when the first pair separated");
  sink.result("fracture_deepest", deepest, "m",
              "deepest separation along the needle path (initial midpoint of the pair, from the entry point)");
  sink.result("fracture_max_offset", widest, "m",
              "largest distance of a separated pair (initial midpoint) from the needle path");
}

// ---------------------------------------------------------------- particle fields

ParticleFields::ParticleFields(io::FieldSeries* series, const MpmSolver& solver, const Vec3& shift,
                               const TissueSpec& tissue)
    : fs_(series), shift_(shift) {
  if (!fs_) return;
  const std::size_t np = solver.size();
  x0_.resize(3 * np);
  for (std::size_t p = 0; p < np; ++p)
    for (int c = 0; c < 3; ++c) x0_[3 * p + static_cast<std::size_t>(c)] = solver.position(p)[c] - shift_[c];
  disp_.resize(3 * np);
  vm_.resize(np);
  fs_->setMesh(x0_, io::CellType::Points, {});
  std::vector<int> region(np);
  for (std::size_t p = 0; p < np; ++p) region[p] = solver.material(p);
  fs_->meshPointLabels("region", region, tissue::regionLegend(tissue));
}

void ParticleFields::write(const MpmSolver& solver, double t) {
  if (!fs_) return;
  for (std::size_t p = 0; p < solver.size(); ++p) {
    const Vec3 x = solver.position(p) - shift_;
    for (int c = 0; c < 3; ++c) {
      const std::size_t i = 3 * p + static_cast<std::size_t>(c);
      disp_[i] = x[c] - x0_[i];
    }
    vm_[p] = vonMises(solver.cauchy(p));
  }
  fs_->beginStep(t);
  fs_->pointData("displacement", disp_, 3, "m");  // on the reference points: Warp By Vector moves them
  fs_->pointData("von_mises", vm_, 1, "Pa");
  fs_->endStep();
}

NeedleFields::NeedleFields(io::FieldSeries* series, const mpm::RigidBody& needle, const Vec3& shift)
    : fs_(series), shift_(shift) {
  if (!fs_) return;
  fs_->setMesh(surfacePoints(needle), io::CellType::Triangle, needleSurfaceOf(needle).cells);
}

std::vector<double> NeedleFields::surfacePoints(const mpm::RigidBody& needle) const {
  std::vector<double> points = needleSurfaceOf(needle).points;
  for (std::size_t i = 0; i < points.size(); ++i) points[i] -= shift_[static_cast<Eigen::Index>(i % 3)];
  return points;
}

void NeedleFields::write(const mpm::RigidBody& needle, double t) {
  if (!fs_) return;
  fs_->beginStep(t);
  fs_->stepPoints(surfacePoints(needle));
  fs_->endStep();
}

// ---------------------------------------------------------------- measured force (eq 35)

ForceError compareForce(const MeasuredCurve& measured, const std::vector<double>& simDepth,
                        const std::vector<double>& simForce) {
  std::vector<double> d, f;
  for (const std::size_t i : mpm::advancingRows(simDepth, d)) f.push_back(simForce[i]);
  ForceError e;
  double s2 = 0.0, s1 = 0.0;
  for (std::size_t k = 0; k < measured.depth.size(); ++k) {
    const double x = measured.depth[k];
    if (d.size() < 2 || x < d.front() || x > d.back()) continue;
    const auto it = std::upper_bound(d.begin(), d.end(), x);
    const std::size_t j = std::min<std::size_t>(static_cast<std::size_t>(it - d.begin()), d.size() - 1);
    const double t = (x - d[j - 1]) / (d[j] - d[j - 1]);
    const double r = measured.force[k] - (f[j - 1] + t * (f[j] - f[j - 1]));
    s2 += r * r;
    s1 += std::abs(r);
    ++e.n;
  }
  if (e.n > 0) {
    e.rmse = std::sqrt(s2 / static_cast<double>(e.n));
    e.mae = s1 / static_cast<double>(e.n);
  }
  return e;
}

}  // namespace needlesim::engines::mpm_outputs
