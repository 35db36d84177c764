#pragma once
// The haptic bridge: a UDP server (docs/haptic-protocol.md) that takes a device's
// pose packets, sets them as the live session's target, and answers each with the
// latest state (forces on the hand), or with the session's refusal of a pose it was moved to
// since the last answer (error code 5). Its own thread; a device sends at 1 kHz.
#include <atomic>
#include <cstdint>
#include <string>
#include <thread>

#include "needlesim/live/haptic_protocol.hpp"
#include "needlesim/live/live_session.hpp"

namespace needlesim::live {

class HapticServer {
 public:
  // Binds host:port (0: any free port); InputError naming --haptic-port when it cannot.
  HapticServer(LiveSession& live, const std::string& host, int port);
  ~HapticServer();
  HapticServer(const HapticServer&) = delete;
  HapticServer& operator=(const HapticServer&) = delete;

  int port() const { return port_; }
  void start();
  void stop();
  std::uint64_t answered() const { return answered_; }
  std::uint64_t refused() const { return refused_; }

 private:
  void run();
  haptic::Bytes answerTo(const haptic::PosePacket& pose);
  LiveSession& live_;
  int fd_ = -1;
  int port_ = 0;
  std::atomic<bool> running_{false};
  std::atomic<std::uint64_t> answered_{0}, refused_{0};
  std::uint64_t sessionRefusals_ = 0;  // the live session's refusals answered so far (its thread)
  std::thread thread_;
};

}  // namespace needlesim::live
