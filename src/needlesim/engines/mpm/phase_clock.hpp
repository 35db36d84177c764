#pragma once
// Wall and process CPU time of each phase of an MPM step, and the time each
// thread worked in the particle passes (bench_mpm --phases prints them).
#include <array>
#include <chrono>
#include <cstddef>
#include <ctime>
#include <vector>

namespace needlesim::mpm {

// Seconds on the steady clock.
inline double wallSeconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}
// CPU seconds of the process, all threads (POSIX).
inline double cpuSeconds() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

class PhaseClock {
 public:
  enum Phase { kSort, kZeroGrid, kScatter, kPenalty, kGridPlan, kGridUpdate, kRigidSums, kContact, kRemap,
               kRemapUpdate, kG2P, kPhases };
  static const char* name(int phase);

  // Summed since the set-up or the last reset (s).
  const std::array<double, kPhases>& wall() const { return wall_; }
  const std::array<double, kPhases>& cpu() const { return cpu_; }
  void add(Phase phase, double wall0, double cpu0, double wall1, double cpu1) {
    wall_[phase] += wall1 - wall0;
    cpu_[phase] += cpu1 - cpu0;
  }
  // Slots for a team of `threads` (before the step's particle passes).
  void sizeFor(int threads) {
    threads_ = static_cast<std::size_t>(threads);
    busy_.resize(kPhases * threads_, 0.0);
  }
  // Thread t's work time in a particle pass (inside its parallel region, each
  // thread adds to its own slot); a pass before sizeFor is not timed.
  void addBusy(Phase phase, int t, double seconds) {
    const std::size_t slot = static_cast<std::size_t>(phase) * threads_ + static_cast<std::size_t>(t);
    if (slot < busy_.size()) busy_[slot] += seconds;
  }
  // The time each thread of a team of `threads` worked in a particle pass,
  // barrier waits left out.
  std::vector<double> busy(Phase phase, int threads) const;
  void reset() {
    wall_.fill(0.0);
    cpu_.fill(0.0);
    busy_.assign(busy_.size(), 0.0);
  }

 private:
  std::array<double, kPhases> wall_{}, cpu_{};
  std::vector<double> busy_;  // [phase][thread]
  std::size_t threads_ = 0;
};

}  // namespace needlesim::mpm
