#pragma once
// A live session: a physics thread steps an api::Session at a fixed dt (1 ms by
// default) towards the latest commanded pose, while viewers and a haptic device
// read the latest state. The exchange is one short mutex hold per publication.
#include <atomic>
#include <chrono>
#include <cstdint>
#include <mutex>
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
  double rate = 0.0;           // Hz, steps per second over the last second
  double punctureDepth = -1.0; // m, depth at the first puncture (phase cutting or later), < 0 before it
  std::uint64_t overruns = 0;  // steps that started more than 10 dt late
  double stepCost = 0.0;       // s, mean wall time of one session step over the last second
  double stepMaxCost = 0.0;    // s, the longest over the last second
};

class LiveSession {
 public:
  LiveSession(const api::Scenario& scenario, const LiveSettings& settings);
  ~LiveSession();
  LiveSession(const LiveSession&) = delete;
  LiveSession& operator=(const LiveSession&) = delete;

  void start();
  void stop();  // joins the physics thread; idempotent

  void setDrive(const Drive& drive);   // held keys and buttons
  void setTarget(const Pose& target);  // an absolute pose (haptic device), followed quickly
  void flipBevel();                    // roll the bevel by half a turn
  // Back to the first step's state (a recording starts over). The physics thread rebuilds the
  // session: for realtime2d a pause of up to a second or two while readers see the last state.
  void reset();

  LatestState latest() const;
  void frame(Frame& out) const;
  // Force-plot samples from index `from` on; `total` is the count there is.
  std::vector<Sample> samples(std::size_t from, std::size_t& total) const;

  const api::Surface& surface() const { return surface_; }
  const std::string& engine() const { return engine_; }
  const Controls& controls() const { return controls_; }
  const LiveSettings& settings() const { return settings_; }
  const api::Scenario& scenario() const { return scenario_; }
  // Every step since the start or the last reset (settings.record), once stopped.
  const StepLog& log() const { return log_; }
  // Mean wall time of one session step since the start (read once stopped).
  double meanStepCost() const { return step_ ? totalCost_ / static_cast<double>(step_) : 0.0; }

 private:
  void run();
  void stepOnce();
  void resetIfAsked();
  void publish(const api::State& state);
  void measureRate(std::chrono::steady_clock::time_point now);

  api::Scenario scenario_;
  LiveSettings settings_;
  api::Session session_;
  api::Surface surface_;
  std::string engine_;
  Controls controls_;

  mutable std::mutex controlMutex_;  // drive, target, mode, reset
  Drive drive_;
  Pose target_;
  bool deviceMode_ = false;
  bool resetRequested_ = false;

  Pose pose_;  // physics thread only
  StepLog log_;
  std::uint64_t step_ = 0;

  mutable std::mutex stateMutex_;  // what follows
  LatestState latest_;
  Frame frame_;
  std::vector<Sample> samples_;

  std::atomic<bool> running_{false};
  std::thread thread_;
  std::chrono::steady_clock::time_point rateWindow_{};
  std::uint64_t rateSteps_ = 0;
  double windowCost_ = 0.0, windowMaxCost_ = 0.0, totalCost_ = 0.0;  // physics thread only
};

}  // namespace needlesim::live
