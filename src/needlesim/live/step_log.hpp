#pragma once
// A live session's record: every step's command and outputs, and the resets between them,
// written as a results folder (commands.csv, forces.csv, summary.json, report.html) and
// replayed through a fresh session (needlesim replay) to reproduce forces.csv.
#include <filesystem>
#include <string>
#include <vector>

#include "needlesim/io/table.hpp"
#include "needlesim/live/pose.hpp"
#include "needlesim/needlesim.hpp"

namespace needlesim::live {

inline constexpr const char* kPhases[] = {"outside", "pressing", "cutting", "inside", "through"};
int phaseIndex(const std::string& phase);  // -1 when unknown

struct StepRecord {
  double time;   // s, since the recording started (the sum of the steps' dt, resets included)
  double dt;
  Pose pose;
  api::State state;
  bool reset;    // the session was reset (rebuilt) before this step
};

class StepLog {
 public:
  void add(double dt, const Pose& pose, const api::State& state) {
    time_ += dt;
    rows_.push_back({time_, dt, pose, state, resetPending_});
    resetPending_ = false;
  }
  // The session was reset: the next step starts from the first step's state.
  void markReset() { resetPending_ = true; }
  void reserve(std::size_t n) { rows_.reserve(n); }
  std::size_t size() const { return rows_.size(); }
  const std::vector<StepRecord>& rows() const { return rows_; }

  // commands.csv: time, dt, depth, lateral, rotation, tilt, roll, reset (1 on the first step
  // after a reset); written exactly (each value reads back as the double that was stepped).
  io::Table commandsTable() const;
  io::Table forcesTable(bool flexible) const;  // forces.csv: the common columns and the parts

 private:
  std::vector<StepRecord> rows_;
  double time_ = 0.0;
  bool resetPending_ = false;
};

// Writes the log as a results folder at `target` (staged, moved into place when complete).
// `replace`: an existing needlesim results folder there may be replaced.
void writeRecording(const api::Scenario& scenario, const StepLog& log, const std::filesystem::path& target,
                    bool replace, double wallSeconds, const std::string& origin);

// Reads a recording's commands (commands.csv) and steps a fresh session of its
// scenario (summary.json) through them.
StepLog replay(const std::filesystem::path& recording, api::Scenario& scenarioOut);

// Largest difference between a replayed forces table and a recorded forces.csv over depth,
// forces, tip position and friction (in their SI units); infinite when the rows differ.
double largestDifference(const io::Table& replayed, const std::filesystem::path& recordedForces);

}  // namespace needlesim::live
