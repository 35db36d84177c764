#pragma once
// Progress on a terminal for anything longer than a few seconds. Quiet when
// asked (--quiet) or when stderr is not a terminal.
#include <chrono>
#include <string>

namespace needlesim {

class Progress {
 public:
  Progress(std::string label, bool enabled);
  ~Progress();
  // fraction in [0, 1]; redraws at most ten times a second.
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
