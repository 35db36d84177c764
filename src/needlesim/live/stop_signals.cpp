// needlesim serve's stop signals (stop_signals.hpp): async-signal-safe handler state only
// (lock-free atomics, a message composed before the handler is installed, write(2)).
#include "needlesim/live/stop_signals.hpp"

#include <unistd.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <csignal>

#include "needlesim/core/progress.hpp"

namespace needlesim::live {

namespace {
std::atomic<bool> gStopping{false};
std::atomic<int> gFurther{0};
std::array<char, 512> gMessage{};
std::size_t gMessageLength = 0;  // 0: no recording, a further signal ends the process
static_assert(std::atomic<bool>::is_always_lock_free && std::atomic<int>::is_always_lock_free);

extern "C" void onServeStopSignal(int signal) {
  if (!gStopping.exchange(true)) {
    requestStop(signal);
    return;
  }
  if (gMessageLength == 0) {  // nothing to lose: stop now, as without the handler
    std::signal(signal, SIG_DFL);
    std::raise(signal);
    return;
  }
  gFurther.fetch_add(1);
  [[maybe_unused]] const ssize_t written = ::write(STDERR_FILENO, gMessage.data(), gMessageLength);
}
}  // namespace

void installServeStopHandlers(const std::string& recording) {
  if (!recording.empty()) {
    const std::string text = "needlesim serve: stopping; the recording is written to " + recording +
                             " first (further signals are ignored; SIGKILL ends at once and loses it)\n";
    gMessageLength = std::min(text.size(), gMessage.size());
    std::copy_n(text.begin(), gMessageLength, gMessage.begin());
    if (gMessageLength == gMessage.size()) gMessage.back() = '\n';
  }
  struct sigaction sa {};
  sa.sa_handler = onServeStopSignal;
  sigemptyset(&sa.sa_mask);
  sa.sa_flags = SA_RESTART;  // system calls (the recording's writes) go on
  for (int s : {SIGINT, SIGTERM}) sigaction(s, &sa, nullptr);
}

void markStopping() { gStopping = true; }
int signalsWhileStopping() { return gFurther.load(); }

}  // namespace needlesim::live
