#include "needlesim/live/live_session.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <stdexcept>

#ifdef __linux__
#include <pthread.h>
#include <sched.h>
#include <sys/resource.h>
#include <unistd.h>
#endif

namespace needlesim::live {

namespace {
using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point before) { return std::chrono::duration<double>(Clock::now() - before).count(); }

// Makes the calling thread yield to the physics thread: the batch policy (waking it does not
// preempt the thread that woke it) at nice 10, so a field computation on the core the physics
// thread runs on gives way to each step.
void yieldToPhysics() {
#ifdef __linux__
  const sched_param none{};
  pthread_setschedparam(pthread_self(), SCHED_BATCH, &none);
  setpriority(PRIO_PROCESS, static_cast<id_t>(gettid()), 10);
#endif
}

// The depth range: from a little outside the entry face to a little past the tissue,
// no deeper than the needle is long.
void depthRange(MotionLimits& limits, const api::Surface& surface, const std::vector<double>& needle) {
  if (limits.maxDepth > 0.0) return;
  double far = 0.0;
  for (std::size_t i = 0; i < surface.vertices.size(); i += 3) far = std::max(far, surface.vertices[i]);
  const std::size_t last = needle.size() - 3;
  const double length = std::hypot(needle[last] - needle[0], needle[last + 1] - needle[1], needle[last + 2] - needle[2]);
  limits.maxDepth = std::min(far + 5e-3, 0.95 * length);
}
}  // namespace

LiveSession::LiveSession(const api::Scenario& scenario, const LiveSettings& settings)
    : scenario_(scenario), settings_(settings), session_(scenario), surface_(session_.surface()),
      inclusions_(session_.inclusions()),
      engine_(session_.engine()), controls_(controlsFor(session_.axes())) {
  if (!(settings_.dt > 0.0) || !std::isfinite(settings_.dt))
    throw api::InputError("the physics step must be a finite time > 0 s", "<live session>", 0, "dt");
  depthRange(settings_.limits, surface_, session_.needleCentreLine(2));
  session_.surfaceField(frame_.field);
  frame_.needle = session_.needleCentreLine();
  latest_.state = session_.state();
  frame_.latest = latest_;
  if (settings_.record) log_.reserve(1 << 16);
}

LiveSession::~LiveSession() { stop(); }

void LiveSession::start() {
  if (running_.exchange(true)) return;
  {
    std::lock_guard lock(snapshotMutex_);
    viewing_ = true;
  }
  viewer_ = std::thread([this] { runViewer(); });
  thread_ = std::thread([this] { run(); });
}

void LiveSession::stop() {
  running_ = false;
  if (thread_.joinable()) thread_.join();
  stopViewer();
}

void LiveSession::advance(int steps) {
  if (running_) throw std::logic_error("LiveSession::advance while the physics thread runs");
  for (int k = 0; k < steps; ++k) stepOnce();
}

void LiveSession::setDrive(const Drive& drive) {
  std::lock_guard lock(controlMutex_);
  drive_ = drive;
  deviceMode_ = false;
}

void LiveSession::setTarget(const Pose& target) {
  std::lock_guard lock(controlMutex_);
  target_ = clampTarget(target, settings_.limits, controls_);
  drive_ = Drive{};
  deviceMode_ = true;
}

void LiveSession::flipBevel() {
  std::lock_guard lock(controlMutex_);
  if (controls_.roll) target_.roll += std::numbers::pi;
}

void LiveSession::reset() {
  std::lock_guard lock(controlMutex_);
  resetRequested_ = true;
}

LatestState LiveSession::latest() const {
  std::lock_guard lock(stateMutex_);
  return latest_;
}

bool LiveSession::refusedSince(std::uint64_t& seen, std::string& message) const {
  std::lock_guard lock(stateMutex_);
  if (frame_.refusals == seen) return false;
  seen = frame_.refusals;
  message = frame_.refusal;
  return true;
}

void LiveSession::frame(Frame& out) const {
  {
    std::lock_guard lock(fieldMutex_);
    out.field = frame_.field;
    out.needle = frame_.needle;
    out.fieldStep = frame_.fieldStep;
    out.fields = frame_.fields;
    out.fieldCost = frame_.fieldCost;
  }
  std::lock_guard lock(stateMutex_);
  out.latest = latest_;
  out.rate = frame_.rate;
  out.punctureDepth = frame_.punctureDepth;
  out.overruns = frame_.overruns;
  out.stepCost = frame_.stepCost;
  out.stepMaxCost = frame_.stepMaxCost;
  out.refusals = frame_.refusals;
  out.refusal = frame_.refusal;
}

std::vector<Sample> LiveSession::samples(std::size_t from, std::size_t& total) const {
  std::lock_guard lock(stateMutex_);
  total = samples_.size();
  if (from >= total) return {};
  return {samples_.begin() + static_cast<std::ptrdiff_t>(from), samples_.end()};
}

void LiveSession::run() {
  const auto dt = std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(settings_.dt));
  Clock::time_point next = Clock::now();
  rateWindow_ = next;
  while (running_) {
    stepOnce();
    next += dt;
    const Clock::time_point now = Clock::now();
    measureRate(now);
    if (now < next) {
      std::this_thread::sleep_until(next);
    } else if (now - next > 10 * dt) {  // far behind (a busy machine): start the schedule afresh
      next = now;
      std::lock_guard lock(stateMutex_);
      ++frame_.overruns;
    }
  }
}

void LiveSession::resetIfAsked() {
  {
    std::lock_guard lock(controlMutex_);
    if (!resetRequested_) return;
    resetRequested_ = false;
    target_ = Pose{};
  }
  {
    std::lock_guard rebuild(rebuildMutex_);  // waits for a field computation to finish
    session_.reset();  // rebuilds the engine's session (for realtime2d: its mesh and factorisation)
  }
  pose_ = Pose{};
  taken_.reset();
  if (settings_.record) log_.markReset();  // the recording goes on: its replay resets here too
  std::lock_guard stateLock(stateMutex_);
  samples_.clear();
  frame_.punctureDepth = -1.0;
}

void LiveSession::stepOnce() {
  resetIfAsked();
  {
    std::lock_guard lock(controlMutex_);
    MotionLimits limits = settings_.limits;
    if (deviceMode_) {
      limits.insertSpeed *= settings_.deviceSpeedFactor;
      limits.lateralSpeed *= settings_.deviceSpeedFactor;
      limits.turnRate *= settings_.deviceSpeedFactor;
    } else {
      driveTarget(target_, drive_, settings_.limits, controls_, settings_.dt);
    }
    approach(pose_, target_, limits, settings_.dt);
  }
  const Clock::time_point before = Clock::now();
  const api::State* state = stepSession();
  if (!state) return;
  ++step_;
  if (settings_.record) log_.add(settings_.dt, pose_, *state);
  publish(*state);
  const double cost = secondsSince(before);
  windowCost_ += cost;
  windowMaxCost_ = std::max(windowMaxCost_, cost);
  totalCost_ += cost;
}

// The session's step to the pose; a pose it refuses is reported, and the session steps at the
// last pose it took (nothing, where it took none yet since the start or reset).
const api::State* LiveSession::stepSession() {
  try {
    const api::State& state = session_.step(commandFor(pose_), settings_.dt);
    taken_ = pose_;
    return &state;
  } catch (const api::InputError& e) {
    noteRefusal(e.what());
    pose_ = taken_.value_or(Pose{});
    if (!taken_) return nullptr;
    return &session_.step(commandFor(pose_), settings_.dt);
  }
}

// The target comes back to the held pose, so that the motion starts again from there.
void LiveSession::noteRefusal(const std::string& message) {
  {
    std::lock_guard lock(controlMutex_);
    target_ = taken_.value_or(Pose{});
  }
  std::lock_guard lock(stateMutex_);
  ++frame_.refusals;
  frame_.refusal = message;
}

void LiveSession::publish(const api::State& state) {
  const bool field = step_ % static_cast<std::uint64_t>(std::max(settings_.fieldEvery, 1)) == 0;
  const bool sample = step_ % static_cast<std::uint64_t>(std::max(settings_.sampleEvery, 1)) == 0;
  if (field) snapshotField();
  std::lock_guard lock(stateMutex_);
  latest_.step = step_;
  latest_.state = state;
  latest_.pose = pose_;
  latest_.at = Clock::now();
  const int phase = phaseIndex(state.phase);
  if (frame_.punctureDepth < 0.0 && phase >= 2) frame_.punctureDepth = state.depth;
  if (sample)
    samples_.push_back({state.time, state.depth, state.axial_force, state.friction_force, state.lateral_force,
                        state.tip_deflection, phase});
}

// Physics thread: hands the viewer thread what this step's field is computed from (a snapshot
// that replaces one it has not taken yet) and the needle's centre line.
void LiveSession::snapshotField() {
  std::vector<double> needle = session_.needleCentreLine();
  {
    std::lock_guard lock(snapshotMutex_);
    session_.snapshotField(pendingSnapshot_);
    pendingNeedle_.swap(needle);
    pendingStep_ = step_;
    snapshotPending_ = true;
  }
  snapshotTaken_.notify_one();
}

// Viewer thread: computes and publishes the field of each snapshot it takes, until stopped.
void LiveSession::runViewer() {
  yieldToPhysics();
  api::FieldSnapshot snapshot;
  api::SurfaceField field;
  std::vector<double> needle;
  std::uint64_t step = 0;
  while (nextSnapshot(snapshot, needle, step)) {
    const Clock::time_point before = Clock::now();
    try {
      computeField(snapshot, field);
    } catch (const std::exception& e) {
      // a snapshot the session can no longer read (taken before a reset) is dropped, never fatal:
      // the next one replaces it; the view keeps the last good field meanwhile
      std::fprintf(stderr, "warning: viewer field of step %llu skipped: %s\n", static_cast<unsigned long long>(step),
                   e.what());
      continue;
    }
    publishField(field, needle, step, secondsSince(before));
  }
}

// Waits for a snapshot and swaps it into `snapshot` (both keep their storage); false once the
// viewer is stopped and none is left.
bool LiveSession::nextSnapshot(api::FieldSnapshot& snapshot, std::vector<double>& needle, std::uint64_t& step) {
  std::unique_lock lock(snapshotMutex_);
  snapshotTaken_.wait(lock, [this] { return snapshotPending_ || !viewing_; });
  if (!snapshotPending_) return false;
  std::swap(snapshot, pendingSnapshot_);
  needle.swap(pendingNeedle_);
  step = pendingStep_;
  snapshotPending_ = false;
  return true;
}

void LiveSession::computeField(const api::FieldSnapshot& snapshot, api::SurfaceField& field) {
  std::lock_guard rebuild(rebuildMutex_);
  session_.surfaceField(snapshot, field);
}

// Swaps the new field and needle into the frame (the old ones' storage comes back for reuse).
void LiveSession::publishField(api::SurfaceField& field, std::vector<double>& needle, std::uint64_t step, double cost) {
  std::lock_guard lock(fieldMutex_);
  std::swap(frame_.field, field);
  frame_.needle.swap(needle);
  frame_.fieldStep = step;
  frame_.fieldCost = cost;
  ++frame_.fields;
}

void LiveSession::stopViewer() {
  {
    std::lock_guard lock(snapshotMutex_);
    viewing_ = false;
  }
  snapshotTaken_.notify_one();
  if (viewer_.joinable()) viewer_.join();
}

void LiveSession::measureRate(Clock::time_point now) {
  ++rateSteps_;
  const double window = std::chrono::duration<double>(now - rateWindow_).count();
  if (window < 1.0) return;
  std::lock_guard lock(stateMutex_);
  frame_.rate = static_cast<double>(rateSteps_) / window;
  frame_.stepCost = windowCost_ / static_cast<double>(rateSteps_);
  frame_.stepMaxCost = windowMaxCost_;
  rateSteps_ = 0;
  windowCost_ = windowMaxCost_ = 0.0;
  rateWindow_ = now;
}

}  // namespace needlesim::live
