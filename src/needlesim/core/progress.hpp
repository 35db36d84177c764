#pragma once
// Progress on a terminal for anything longer than a few seconds, and stop
// requests (Ctrl-C, SIGTERM) for the same loops. Quiet when asked (--quiet)
// or when stderr is not a terminal.
#include <chrono>
#include <filesystem>
#include <string>

#include "needlesim/core/error.hpp"

namespace needlesim {

// A run stopped before its end: by a stop request (signal() is SIGINT or
// SIGTERM) or by the test hook RunOptions::stopAfterSteps (signal() is 0).
// Nothing is committed; an engine with checkpoints has written one.
class RunInterrupted : public Error {
 public:
  explicit RunInterrupted(const std::string& what, int signal = 0) : Error(what), signal_(signal) {}
  int signal() const { return signal_; }

 private:
  int signal_;
};

// Stop requests. installStopHandlers() makes SIGINT and SIGTERM set a flag
// (a second one of the same signal ends the process at once, as without the
// handler): it blocks them in the calling thread and the threads it starts
// later, and one thread of its own takes them (sigwait), so a library's
// passing handler cannot swallow them. Call it before starting threads.
// Engines' loops, set-up included, see the flag through Progress::update
// or throwIfStopRequested (or ask stopRequested() where they write a
// checkpoint first).
void installStopHandlers();
bool stopRequested();
int stopSignal();  // the signal that asked for the stop, 0 when none
std::string stopSignalName();  // "SIGINT (Ctrl-C)", "SIGTERM", ... ("" when none)
void requestStop(int signal);  // what the handlers call (tests call it directly)
void clearStopRequest();
// Throws RunInterrupted("<what>: interrupted by SIGINT ...") when a stop was requested.
void throwIfStopRequested(const std::string& what);

// One library call that cannot look at stop requests and may run for seconds
// (a sparse factorisation). Opening one first checks for a stop request
// (throwIfStopRequested(what)). In a command that called
// exitOnStopInBlockingCalls, a stop request while one is open ends the process
// within half a second, as RunInterrupted would: the paths registered with
// removeIfStoppedHard are removed, "stopped: <what>: interrupted by <signal>
// <note>" is printed on stderr and the exit code is 128 + the signal.
// Elsewhere (needlesim serve, which must write its recording; Python) the call
// runs to its end and the next check stops.
class BlockingCall {
 public:
  explicit BlockingCall(const std::string& what);
  ~BlockingCall();
  BlockingCall(const BlockingCall&) = delete;
  BlockingCall& operator=(const BlockingCall&) = delete;
};

// Lets a stop inside a BlockingCall end the process (for commands that have
// nothing to save on a stop: run, sweep); `note` ends its line ("; nothing was
// written to ...", as the command's own RunInterrupted message says). What it
// removes before the process ends: the paths given to removeIfStoppedHard
// (staging folders, lock files); forgetOnStop takes a path off the list.
void exitOnStopInBlockingCalls(const std::string& note);
void removeIfStoppedHard(const std::filesystem::path& path);
void forgetOnStop(const std::filesystem::path& path);

class Progress {
 public:
  Progress(std::string label, bool enabled);
  ~Progress();
  // fraction in [0, 1]; redraws at most ten times a second. Every call first
  // checks for a stop request: throwIfStopRequested(label).
  void update(double fraction, const std::string& detail = {});
  void finish();

  static bool stderrIsTerminal();

 private:
  std::string label_;
  bool enabled_;
  bool drawn_ = false;
  std::chrono::steady_clock::time_point start_, last_;
};

}  // namespace needlesim
