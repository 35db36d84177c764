// The phase names and per-thread work times of an MPM step (phase_clock.hpp).
#include "needlesim/engines/mpm/phase_clock.hpp"

namespace needlesim::mpm {

const char* PhaseClock::name(int phase) {
  static constexpr std::array<const char*, kPhases> names = {
      "sort by block", "fork + zero grid",   "scatter (p2g)", "penalty contact", "grid row plan", "grid update",
      "rigid force sums", "contact: cut, CFEMP", "remap (g2p)", "remap update", "g2p + stress"};
  return phase >= 0 && phase < kPhases ? names[static_cast<std::size_t>(phase)] : "?";
}

std::vector<double> PhaseClock::busy(Phase phase, int threads) const {
  const auto T = static_cast<std::size_t>(threads);
  if (busy_.size() != kPhases * T) return std::vector<double>(T, 0.0);
  const auto first = busy_.begin() + static_cast<std::ptrdiff_t>(static_cast<std::size_t>(phase) * T);
  return {first, first + static_cast<std::ptrdiff_t>(T)};
}

}  // namespace needlesim::mpm
