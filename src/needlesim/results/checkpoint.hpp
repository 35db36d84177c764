#pragma once
// Checkpoints of long runs, so that a run that was stopped (killed, power
// cut, out of time on a cluster) can go on with `needlesim run --resume`.
//
// Folder <target>.checkpoint/ beside the results target (for the automatic
// target results/<name>, always results/<name>.checkpoint, whichever -2, -3
// suffix the results get), holding
//   state.bin        the state (binary_state.hpp, kind "checkpoint"): the
//                    scenario fingerprint, the engine, the simulated time and
//                    step, the field series so far, the engine's own state;
//   <series>.<n>.h5  a copy of each field series' HDF5 file at that step.
// Written in an order that keeps the last checkpoint valid at every moment:
// the HDF5 copies under new names first (temporary file + rename), then
// state.bin atomically (temporary file + rename), then the copies state.bin
// no longer names are deleted. runScenario deletes the folder once the results
// folder is committed. The engine decides where a step ends (mpm: engines/
// mpm/mpm_engine.cpp); other engines do not write checkpoints yet.
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "needlesim/io/binary_state.hpp"
#include "needlesim/scenario/scenario.hpp"

namespace needlesim::io {

class FieldSeries;

class Checkpoint {
 public:
  static constexpr std::uint32_t kVersion = 1;  // of state.bin's layout (engines add their own)

  struct Settings {
    std::filesystem::path folder;  // <target>.checkpoint (folderFor)
    std::string fingerprint;       // scenarioFingerprint of the scenario run
    double interval = 600.0;       // s of wall-clock time between checkpoints; <= 0: never
    long long everySteps = 0;      // test hook: also after every N steps (0: off)
    bool resume = false;           // load the checkpoint in the folder before the first step
    bool progress = false;         // one line on stderr per checkpoint written
  };
  using Series = std::vector<std::pair<std::string, FieldSeries*>>;

  explicit Checkpoint(Settings settings);
  const Settings& settings() const { return s_; }
  static std::filesystem::path folderFor(const std::filesystem::path& target);
  std::filesystem::path stateFile() const { return s_.folder / "state.bin"; }

  // Engine side: is a checkpoint due after `steps` steps (the wall-clock
  // interval since the last one or the start, or the step hook)?
  bool due(long long steps) const;
  // Writes the engine's state with the field series (name, series).
  void write(std::string_view engine, const BinaryWriter& state, const Series& fields, double time, long long steps);
  int written() const { return written_; }

  // Resume: checks the file (InputError naming it when missing, truncated,
  // corrupt, of another scenario or engine), restores the field series and
  // returns a reader over the engine's state.
  bool resuming() const { return s_.resume; }
  BinaryReader load(std::string_view engine, const Series& fields);
  // The same checks of the file and its header, without restoring anything
  // (needlesim run --resume, before the set-up).
  void check(std::string_view engine) const;
  double resumedTime() const { return resumedTime_; }
  long long resumedSteps() const { return resumedSteps_; }

  // Deletes the folder (after the results were committed).
  void remove();

 private:
  Settings s_;
  std::chrono::steady_clock::time_point last_;
  std::uint64_t seq_ = 0;
  int written_ = 0;
  double resumedTime_ = 0.0;
  long long resumedSteps_ = 0;
};

// Whether `dir` is a checkpoint folder needlesim wrote (before --overwrite
// deletes it): every entry is state.bin (starting with the state-file magic),
// a <series>.<n>.h5 copy or a temporary of one of them.
bool isCheckpointFolder(const std::filesystem::path& dir);

// Identifies a scenario for --resume: FNV-1a 64 (hex) of the scenario as
// understood (Scenario::understood, every field) and of the text of its file
// (sc.source, when it is a readable file). Any edit to the file, comments
// included, changes it.
std::string scenarioFingerprint(const Scenario& sc);

}  // namespace needlesim::io
