// MpmSolver checkpoints: the state that carries from one step to the next
// (docs/models/mpm.md "Checkpoints"). Everything else (the grid records,
// velocities, contact flags, cell occupancy, pair lists) is rebuilt by the
// next step from the particles: a solver set up the same way, finalized and
// loaded, takes the same next step bit for bit.
#include <fmt/format.h>

#include "needlesim/core/error.hpp"
#include "needlesim/engines/mpm/mpm_solver.hpp"

namespace needlesim::mpm {
namespace {
constexpr std::uint32_t kLayout = 2;  // of the records below; raise on any change

void putVec(io::BinaryWriter& w, const Vec3& v) {
  for (int d = 0; d < 3; ++d) w.pod(v[d]);
}
Vec3 getVec(io::BinaryReader& r) {
  Vec3 v;
  for (int d = 0; d < 3; ++d) r.pod(v[d]);
  return v;
}
}  // namespace

void MpmSolver::saveState(io::BinaryWriter& w) const {
  w.tag("mpm_solver");
  w.pod(kLayout);
  w.pod(static_cast<std::uint32_t>(sizeof(Point)));
  w.pod(static_cast<std::uint64_t>(size()));
  w.pod(static_cast<std::uint64_t>(nodes_));
  w.pod(static_cast<std::int32_t>(cfg_.bodies));
  w.pod(static_cast<std::uint64_t>(mats_.size()));
  w.pod(static_cast<std::uint64_t>(rigids_.size()));
  w.pod(static_cast<std::int32_t>(nthreads_));
  w.vec(body_);
  w.vec(mat_);
  w.tag("particles");
  w.vec(P_);
  w.tag("clock");
  w.pod(time_);
  w.pod(steps_);
  w.pod(maxSpeed_);  // the next step's dt (eqs 25-26)
  w.pod(dt_);
  w.pod(last_);
  w.tag("rigids");
  for (std::size_t r = 0; r < rigids_.size(); ++r) {
    const RigidBody& b = rigids_[r];
    for (const Vec3* v : {&b.point, &b.normal, &b.axis, &b.bevelSide, &b.velocity}) putVec(w, *v);
    const RigidForce& f = rforce_[r];
    for (const Vec3* v : {&f.total, &f.tip, &f.shaft}) putVec(w, *v);
    w.pod(static_cast<std::int32_t>(f.contactNodes));
  }
  // The scatter order (the summation order of p2g) and when to plan it again.
  w.tag("scatter");
  scatter_.save(w);
  w.vec(nearCell_);
  // Two-body penalty contact: the last step's tally sets the next step's limit.
  w.tag("penalty");
  w.pod(static_cast<std::uint8_t>(penalty_.has_value()));
  if (penalty_) w.pod(penalty_->tally_);
  w.tag("end");
}

void MpmSolver::loadState(io::BinaryReader& r) {
  if (!finalized_) finalize();
  r.tag("mpm_solver");
  const auto layout = r.pod<std::uint32_t>();
  if (layout != kLayout)
    r.fail(fmt::format("holds an mpm solver state of layout {}, this needlesim reads layout {}", layout, kLayout));
  if (r.pod<std::uint32_t>() != sizeof(Point)) r.fail("holds particle records of another size (another build)");
  auto check = [&](std::uint64_t got, std::uint64_t want, const char* what) {
    if (got != want) r.mismatch(what, got, want);
  };
  check(r.pod<std::uint64_t>(), size(), "material points");
  check(r.pod<std::uint64_t>(), nodes_, "grid nodes");
  check(static_cast<std::uint64_t>(r.pod<std::int32_t>()), static_cast<std::uint64_t>(cfg_.bodies), "deformable bodies");
  check(r.pod<std::uint64_t>(), mats_.size(), "materials");
  check(r.pod<std::uint64_t>(), rigids_.size(), "rigid bodies");
  const auto threads = r.pod<std::int32_t>();
  if (threads != nthreads_)
    r.fail(fmt::format("was written by a run on {} thread(s), this one has {}: the scatter order and so the last "
                       "bits of every sum depend on it; resume with OMP_NUM_THREADS={} (model.mpm.threads: 0 takes "
                       "all cores; editing the scenario would make the checkpoint another scenario's)",
                       threads, nthreads_, threads));
  if (r.vec<std::uint8_t>(size(), "body indices") != body_) r.fail("assigns the points to other bodies (another set-up)");
  if (r.vec<std::uint8_t>(size(), "material indices") != mat_) r.fail("assigns the points other materials (another set-up)");
  r.tag("particles");
  std::vector<Point> P = r.vec<Point>(size(), "particle records");
  r.tag("clock");
  double time, maxSpeed, dt;
  long long steps;
  StepReport last;
  r.pod(time);
  r.pod(steps);
  r.pod(maxSpeed);
  r.pod(dt);
  r.pod(last);
  r.tag("rigids");
  std::vector<RigidBody> rigids = rigids_;
  std::vector<RigidForce> rforce(rigids_.size());
  for (std::size_t i = 0; i < rigids.size(); ++i) {
    RigidBody& b = rigids[i];
    for (Vec3* v : {&b.point, &b.normal, &b.axis, &b.bevelSide, &b.velocity}) *v = getVec(r);
    RigidForce& f = rforce[i];
    for (Vec3* v : {&f.total, &f.tip, &f.shaft}) *v = getVec(r);
    f.contactNodes = r.pod<std::int32_t>();
  }
  r.tag("scatter");
  BlockColouring scatter = scatter_.read(r, size());
  std::vector<std::uint32_t> nearCell = r.vec<std::uint32_t>(nearCell_.size(), "near-body cell entries");
  r.tag("penalty");
  const bool hasPenalty = r.pod<std::uint8_t>() != 0;
  if (hasPenalty != penalty_.has_value()) r.fail("has another two-body contact (another set-up)");
  PenaltyTally tally;
  if (hasPenalty) r.pod(tally);
  r.tag("end");
  if (!r.atEnd()) r.fail("has data after the mpm solver state (damaged file)");

  // All read and checked: install.
  P_ = std::move(P);
  time_ = time;
  steps_ = steps;
  maxSpeed_ = maxSpeed;
  dt_ = dt;
  last_ = last;
  rigids_ = std::move(rigids);
  rforce_ = std::move(rforce);
  scatter_ = std::move(scatter);
  nearCell_ = std::move(nearCell);
  if (penalty_) penalty_->tally_ = tally;
  gridClean_ = false;  // the next scatter clears the whole grid
  nearBodies_.setFresh(false);  // the next mark marks the cells from the loaded positions
  dropDeviceState();   // GPU back-end: the next step uploads the loaded state
}

}  // namespace needlesim::mpm
