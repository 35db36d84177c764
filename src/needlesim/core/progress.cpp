#include "needlesim/core/progress.hpp"

#include <fmt/format.h>
#include <pthread.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <mutex>
#include <thread>
#include <vector>

namespace needlesim {

namespace {
std::atomic<int> gStopSignal{0};
static_assert(std::atomic<int>::is_always_lock_free, "the stop flag is set from a signal handler");

// A stop signal: the first sets the flag, a second of the same signal ends the process as
// without a handler (default action, raised in this thread with the signal unblocked).
void takeStopSignal(int signal) {
  if (gStopSignal.load() != signal) {
    gStopSignal.store(signal);
    return;
  }
  std::signal(signal, SIG_DFL);
  sigset_t one;
  sigemptyset(&one);
  sigaddset(&one, signal);
  pthread_sigmask(SIG_UNBLOCK, &one, nullptr);
  std::raise(signal);
}

// The handler, for a thread that does not block the stop signals (one started before
// installStopHandlers; needlesim's commands start none).
extern "C" void onStopSignal(int signal) { takeStopSignal(signal); }

// The stop signals' own thread: every other thread blocks them, so they wait here whatever
// handler a library installs for a while. METIS (CHOLMOD's ordering) traps SIGTERM and SIGABRT
// during each of its calls and restores the previous handler after it: a stop request that
// arrived then was swallowed, and the run went on to its end.
void waitForStopSignals(sigset_t set) {
  for (;;) {
    int signal = 0;
    if (sigwait(&set, &signal) == 0) takeStopSignal(signal);
  }
}
}  // namespace

namespace {
// The open BlockingCalls (what the latest one does) and the paths a hard stop removes.
struct HardStop {
  std::mutex mutex;
  int open = 0;
  std::string what;
  std::vector<std::filesystem::path> paths;
  std::string note;
};
HardStop& hardStop() {
  static HardStop* h = new HardStop;  // never destroyed: the watcher may use it while the process ends
  return *h;
}

[[noreturn]] void stopHard(const std::string& what) {
  auto& h = hardStop();
  for (auto it = h.paths.rbegin(); it != h.paths.rend(); ++it) {
    std::error_code ec;
    std::filesystem::remove_all(*it, ec);
  }
  std::fflush(stdout);
  fmt::print(stderr, "\nstopped: {}: interrupted by {}{}\n", what, stopSignalName(), h.note);
  std::fflush(stderr);
  std::_Exit(128 + stopSignal());
}

// Ends the process when a stop request has waited 0.4 s on an open BlockingCall.
void watchBlockingCalls() {
  using clock = std::chrono::steady_clock;
  clock::time_point seen{};
  for (;;) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    auto& h = hardStop();
    std::lock_guard<std::mutex> lock(h.mutex);
    if (!stopRequested() || h.open == 0) {
      seen = {};
      continue;
    }
    if (seen == clock::time_point{}) seen = clock::now();
    if (clock::now() - seen > std::chrono::milliseconds(400)) stopHard(h.what);
  }
}
}  // namespace

void installStopHandlers() {
  static std::once_flag installed;
  std::call_once(installed, [] {
    sigset_t set;
    sigemptyset(&set);
    for (int s : {SIGINT, SIGTERM}) sigaddset(&set, s);
    pthread_sigmask(SIG_BLOCK, &set, nullptr);  // this thread and every thread it starts from now on
    struct sigaction sa {};
    sa.sa_handler = onStopSignal;
    sigemptyset(&sa.sa_mask);
    sa.sa_flags = SA_RESTART;  // system calls (file writes) go on
    for (int s : {SIGINT, SIGTERM}) sigaction(s, &sa, nullptr);
    std::thread(waitForStopSignals, set).detach();
  });
}

BlockingCall::BlockingCall(const std::string& what) {
  throwIfStopRequested(what);
  auto& h = hardStop();
  std::lock_guard<std::mutex> lock(h.mutex);
  ++h.open;
  h.what = what;
}

BlockingCall::~BlockingCall() {
  auto& h = hardStop();
  std::lock_guard<std::mutex> lock(h.mutex);
  --h.open;
}

void removeIfStoppedHard(const std::filesystem::path& path) {
  auto& h = hardStop();
  std::lock_guard<std::mutex> lock(h.mutex);
  h.paths.push_back(path);
}

void exitOnStopInBlockingCalls(const std::string& note) {
  {
    auto& h = hardStop();
    std::lock_guard<std::mutex> lock(h.mutex);
    h.note = note;
  }
  static std::once_flag started;
  std::call_once(started, [] { std::thread(watchBlockingCalls).detach(); });
}

void forgetOnStop(const std::filesystem::path& path) {
  auto& h = hardStop();
  std::lock_guard<std::mutex> lock(h.mutex);
  const auto it = std::find(h.paths.rbegin(), h.paths.rend(), path);
  if (it != h.paths.rend()) h.paths.erase(std::next(it).base());
}

bool stopRequested() { return gStopSignal.load(std::memory_order_relaxed) != 0; }
int stopSignal() { return gStopSignal.load(); }
void requestStop(int signal) { gStopSignal.store(signal); }
void clearStopRequest() { gStopSignal.store(0); }

std::string stopSignalName() {
  const int s = stopSignal();
  return s == SIGINT ? "SIGINT (Ctrl-C)" : s == SIGTERM ? "SIGTERM" : s == 0 ? "" : strsignal(s);
}

void throwIfStopRequested(const std::string& what) {
  const int s = stopSignal();
  if (s == 0) return;
  throw RunInterrupted(fmt::format("{}: interrupted by {}", what, stopSignalName()), s);
}

bool Progress::stderrIsTerminal() { return isatty(fileno(stderr)) != 0; }

Progress::Progress(std::string label, bool enabled)
    : label_(std::move(label)),
      enabled_(enabled && stderrIsTerminal()),
      start_(std::chrono::steady_clock::now()),
      last_(start_) {}

Progress::~Progress() { finish(); }

void Progress::update(double fraction, const std::string& detail) {
  if (stopRequested()) {
    finish();
    throwIfStopRequested(label_);
  }
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
