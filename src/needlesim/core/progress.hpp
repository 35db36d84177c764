#pragma once
// Progress on a terminal for anything longer than a few seconds, and stop
// requests (Ctrl-C, SIGTERM) for the same loops. Quiet when asked (--quiet)
// or when stderr is not a terminal.
#include <chrono>
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
// handler); engines' step loops see it through Progress::update (or ask
// stopRequested() where they write a checkpoint first).
void installStopHandlers();
bool stopRequested();
int stopSignal();  // the signal that asked for the stop, 0 when none
std::string stopSignalName();  // "SIGINT (Ctrl-C)", "SIGTERM", ... ("" when none)
void requestStop(int signal);  // what the handlers call (tests call it directly)
void clearStopRequest();
// Throws RunInterrupted("<what>: interrupted by SIGINT ...") when a stop was requested.
void throwIfStopRequested(const std::string& what);

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
