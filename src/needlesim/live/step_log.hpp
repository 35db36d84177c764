#pragma once
// A live session's record: every step's command and outputs, written as a results
// folder (commands.csv, forces.csv, summary.json, report.html) and replayed through a
// fresh session (needlesim replay) to reproduce forces.csv.
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
  double dt;
  Pose pose;
  api::State state;
};

class StepLog {
 public:
  void add(double dt, const Pose& pose, const api::State& state) { rows_.push_back({dt, pose, state}); }
  void clear() { rows_.clear(); }
  void reserve(std::size_t n) { rows_.reserve(n); }
  std::size_t size() const { return rows_.size(); }
  const std::vector<StepRecord>& rows() const { return rows_; }

  io::Table commandsTable() const;  // commands.csv: time, dt, depth, lateral, rotation, tilt, roll
  io::Table forcesTable(bool flexible) const;  // forces.csv: the common columns and the parts

 private:
  std::vector<StepRecord> rows_;
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
