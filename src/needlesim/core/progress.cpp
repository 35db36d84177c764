#include "needlesim/core/progress.hpp"

#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>

namespace needlesim {

bool Progress::stderrIsTerminal() { return isatty(fileno(stderr)) != 0; }

Progress::Progress(std::string label, bool enabled)
    : label_(std::move(label)),
      enabled_(enabled && stderrIsTerminal()),
      start_(std::chrono::steady_clock::now()),
      last_(start_) {}

Progress::~Progress() { finish(); }

void Progress::update(double fraction, const std::string& detail) {
  if (!enabled_) return;
  auto now = std::chrono::steady_clock::now();
  if (drawn_ && now - last_ < std::chrono::milliseconds(100)) return;
  last_ = now;
  drawn_ = true;
  fraction = std::clamp(fraction, 0.0, 1.0);
  double elapsed = std::chrono::duration<double>(now - start_).count();
  double eta = fraction > 1e-6 ? elapsed * (1.0 - fraction) / fraction : 0.0;
  int width = 30;
  int filled = static_cast<int>(fraction * width);
  fmt::print(stderr, "\r{} [{}{}] {:5.1f}%  {:.1f}s elapsed, ~{:.1f}s left {}   ", label_,
             std::string(filled, '#'), std::string(width - filled, '.'), 100.0 * fraction, elapsed,
             eta, detail);
  std::fflush(stderr);
}

void Progress::finish() {
  if (enabled_ && drawn_) {
    fmt::print(stderr, "\n");
    drawn_ = false;
  }
  enabled_ = false;
}

}  // namespace needlesim
