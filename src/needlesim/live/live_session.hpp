#pragma once
// A live session: a physics thread steps an api::Session at a fixed dt (1 ms by
// default) towards the latest commanded pose, while viewers and a haptic device
// read the latest state. The exchange is one short mutex hold per publication.
// The viewer's surface field is computed in a viewer thread: every fieldEvery steps the
// physics thread only copies the state the field is computed from (api::FieldSnapshot) and
// the needle's centre line; the viewer thread computes the field from that copy while the
// physics thread steps on, and publishes it with the step it belongs to.
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "needlesim/live/pose.hpp"
#include "needlesim/live/step_log.hpp"
#include "needlesim/needlesim.hpp"

namespace needlesim::live {

struct LiveSettings {
  double dt = 1e-3;         // s, physics step
  bool record = false;      // keep every step's command and outputs (StepLog)
  MotionLimits limits;      // key and button motion; depth range set from the scenario when maxDepth <= 0
  double deviceSpeedFactor = 20.0;  // a haptic device's target is followed this much faster
  int fieldEvery = 16;      // steps between surface field publications (~60 Hz at 1 ms)
  int sampleEvery = 10;     // steps between force-plot samples (100 Hz at 1 ms)
};

// The latest step as every reader sees it.
struct LatestState {
  std::uint64_t step = 0;
  api::State state;
  Pose pose;
  std::chrono::steady_clock::time_point at{};
};

// A force-plot point.
struct Sample {
  double time, depth, axial, friction, lateral, deflection;
  int phase;  // index of kPhases
};

// What a viewer draws at display rate.
struct Frame {
  LatestState latest;
  api::SurfaceField field;
  std::vector<double> needle;  // x y z per point, base to tip
  std::uint64_t fieldStep = 0; // the step field and needle belong to
  std::uint64_t fields = 0;    // fields the viewer thread has computed since the start
  double fieldCost = 0.0;      // s, wall time of the viewer thread's last field computation
  double rate = 0.0;           // Hz, steps per second over the last second
  double punctureDepth = -1.0; // m, depth at the first puncture (phase cutting or later), < 0 before it
  std::uint64_t overruns = 0;  // steps that started more than 10 dt late
  // The physics thread's work per step (the session step, recording, publication, the field
  // snapshot), wall time over the last second:
  double stepCost = 0.0;       // s, mean
  double stepMaxCost = 0.0;    // s, the longest
  // Commands the session refused (its step guard: a jump longer than one step may take, a pose
  // out of the tissue's reach): how many, and the last one's message. The pose holds where the
  // session last took it.
  std::uint64_t refusals = 0;
  std::string refusal;
};

class LiveSession {
 public:
  LiveSession(const api::Scenario& scenario, const LiveSettings& settings);
  ~LiveSession();
  LiveSession(const LiveSession&) = delete;
  LiveSession& operator=(const LiveSession&) = delete;

  void start();  // starts the physics and viewer threads
  // Joins the physics thread, then the viewer thread once it has computed the field of the last
  // snapshot; idempotent.
  void stop();
  // Runs `steps` of the physics thread's work in the caller's thread, without the clock, before
  // start() or after stop(): tests and scripted runs. The fields of their snapshots are computed
  // once the viewer thread runs (start()).
  void advance(int steps);

  void setDrive(const Drive& drive);   // held keys and buttons
  void setTarget(const Pose& target);  // an absolute pose (haptic device), followed quickly
  void flipBevel();                    // roll the bevel by half a turn
  // Back to the first step's state (the recording marks it). The physics thread rebuilds the
  // session: for realtime2d a pause of up to a second or two while readers see the last state.
  void reset();

  LatestState latest() const;
  // Whether the session refused a command since `seen` refusals (then `seen` is brought up to
  // date and `message` is the last one's).
  bool refusedSince(std::uint64_t& seen, std::string& message) const;
  void frame(Frame& out) const;
  // Force-plot samples from index `from` on; `total` is the count there is.
  std::vector<Sample> samples(std::size_t from, std::size_t& total) const;

  const api::Surface& surface() const { return surface_; }
  const std::vector<api::Inclusion>& inclusions() const { return inclusions_; }
  const std::string& engine() const { return engine_; }
  const Controls& controls() const { return controls_; }
  const LiveSettings& settings() const { return settings_; }
  const api::Scenario& scenario() const { return scenario_; }
  // Every step since the start, resets marked (settings.record), once stopped.
  const StepLog& log() const { return log_; }
  // Mean wall time of one session step since the start (read once stopped).
  double meanStepCost() const { return step_ ? totalCost_ / static_cast<double>(step_) : 0.0; }

 private:
  void run();
  void stepOnce();
  void resetIfAsked();
  const api::State* stepSession();
  void noteRefusal(const std::string& message);
  void publish(const api::State& state);
  void snapshotField();
  void measureRate(std::chrono::steady_clock::time_point now);
  void runViewer();
  bool nextSnapshot(api::FieldSnapshot& snapshot, std::vector<double>& needle, std::uint64_t& step);
  void computeField(const api::FieldSnapshot& snapshot, api::SurfaceField& field);
  void publishField(api::SurfaceField& field, std::vector<double>& needle, std::uint64_t step, double cost);
  void stopViewer();

  api::Scenario scenario_;
  LiveSettings settings_;
  api::Session session_;
  api::Surface surface_;
  std::vector<api::Inclusion> inclusions_;
  std::string engine_;
  Controls controls_;

  mutable std::mutex controlMutex_;  // drive, target, mode, reset
  Drive drive_;
  Pose target_;
  bool deviceMode_ = false;
  bool resetRequested_ = false;

  Pose pose_;  // physics thread only
  std::optional<Pose> taken_;  // the last pose the session took since the start or reset (physics thread)
  StepLog log_;
  std::uint64_t step_ = 0;

  mutable std::mutex stateMutex_;  // what follows, but for frame_'s field part
  LatestState latest_;
  Frame frame_;
  std::vector<Sample> samples_;
  // frame_'s field part (field, needle, fieldStep, fields, fieldCost): written by the viewer
  // thread, so that copying a large field for a reader never holds up the physics thread.
  mutable std::mutex fieldMutex_;

  // The latest field snapshot, from the physics thread to the viewer thread.
  std::mutex snapshotMutex_;
  std::condition_variable snapshotTaken_;
  api::FieldSnapshot pendingSnapshot_;
  std::vector<double> pendingNeedle_;
  std::uint64_t pendingStep_ = 0;
  bool snapshotPending_ = false;
  bool viewing_ = false;  // the viewer thread waits for snapshots
  // Held by the viewer thread while it computes a field and by the physics thread while a reset
  // rebuilds the session (what the computation reads); never by a step.
  std::mutex rebuildMutex_;

  std::atomic<bool> running_{false};
  std::thread thread_, viewer_;
  std::chrono::steady_clock::time_point rateWindow_{};
  std::uint64_t rateSteps_ = 0;
  double windowCost_ = 0.0, windowMaxCost_ = 0.0, totalCost_ = 0.0;  // physics thread only
};

}  // namespace needlesim::live
