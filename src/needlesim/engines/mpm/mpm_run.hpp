#pragma once
// One mpm run (runMpm): set-up, the step loop, the output rows, checkpoints and
// the results at the end, as named steps.
#include <chrono>
#include <string>
#include <vector>

#include "needlesim/engines/mpm/mpm_engine.hpp"
#include "needlesim/engines/mpm/mpm_outputs.hpp"
#include "needlesim/insertion/motion_profile.hpp"
#include "needlesim/results/forces_table.hpp"
#include "needlesim/results/inclusion_motion.hpp"

namespace needlesim::engines {

class MpmRun {
 public:
  MpmRun(const Scenario& sc, ResultSink& sink, const RunOptions& options);
  // The insertion to the end; the results go to the sink (also when the solver fails).
  void run();

 private:
  using Vec3 = mpm::Vec3;
  // The needle's contact force summed over the steps of one output interval
  // (a row holds the impulse average: the force of a single explicit step is noisy).
  struct Impulses {
    Vec3 total = Vec3::Zero(), tip = Vec3::Zero(), shaft = Vec3::Zero();
    double time = 0.0;
    int contactNodes = 0;
  };
  // What the results report besides the tables.
  struct Summary {
    double peak = 0.0, peakDepth = 0.0, lastForce = 0.0, lastTip = 0.0, lastShaft = 0.0;
    double dtMin = 0.0, dtMax = 0.0;
    long long steps = 0;
  };
  // When the next rows are due.
  struct Schedule {
    double nextOut = 0.0, nextField = 0.0, nextMarkerDepth = 0.0;
  };

  void placeAt(double t);
  Vec3 bevelSideAt(const MotionState& m) const;
  void writeFields(double t);
  void startFresh();
  void step();
  void recordRow(double t, const mpm::StepReport& rep);
  void recordInclusions(double t);
  bool finished(double t) const;
  void saveCheckpoint();
  void loadCheckpoint();
  void emit(bool stopped);
  void emitForces(bool stopped);
  void emitMarkers(bool stopped);
  void emitEnergy();
  void runNotes(double seconds);
  void warnUnresolvedLateralForce();

  std::chrono::steady_clock::time_point wall0_ = std::chrono::steady_clock::now();
  const Scenario& sc_;
  const MpmModelSpec& spec_;
  ResultSink& sink_;
  const RunOptions& options_;
  MpmSetup setup_;
  mpm::MpmSolver solver_;
  std::vector<std::vector<std::size_t>> inclusionPoints_;
  std::vector<Vec3> inclusionStart_;  // mean initial position of each inclusion's points
  static constexpr int kNeedle = 0;  // the needle is the solver's rigid body 0
  double setupSeconds_ = 0.0;
  MotionProfile motion_;
  double duration_ = 0.0;
  MotionState ms_;
  results::ForcesTable forces_;
  io::Table energy_;
  mpm_outputs::MarkerSet markers_;
  mpm_outputs::FractureTracker fracture_;
  mpm_outputs::ParticleFields fields_;
  mpm_outputs::NeedleFields needleFields_;
  results::InclusionMotion inclusions_;
  Impulses imp_;
  Summary sum_;
  Schedule next_;
  long long steps0_ = 0;
  std::string resumedNote_;
};

}  // namespace needlesim::engines
