#include "needlesim/live/haptic_server.hpp"

#include <sys/socket.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cstring>

#include "needlesim/core/error.hpp"
#include "needlesim/live/haptic_protocol.hpp"
#include "needlesim/live/net_address.hpp"

namespace needlesim::live {

namespace {

haptic::StatePacket stateFor(const LatestState& latest, const haptic::PosePacket& pose) {
  const api::State& s = latest.state;
  haptic::StatePacket out;
  out.sequence = pose.sequence;
  out.clientTimeNs = pose.clientTimeNs;
  out.phase = static_cast<std::uint32_t>(std::max(phaseIndex(s.phase), 0));
  out.step = latest.step;
  out.time = s.time;
  out.depth = s.depth;
  out.force = {-s.axial_force, s.lateral_force, 0.0};  // the tissue pushes back against insertion
  out.axialForce = s.axial_force;
  out.frictionForce = s.friction_force;
  out.tipDeflection = s.tip_deflection;
  out.stateAge = std::chrono::duration<double>(std::chrono::steady_clock::now() - latest.at).count();
  return out;
}

}  // namespace

HapticServer::HapticServer(LiveSession& live, const std::string& host, int port) : live_(live) {
  sockaddr_in a = socketAddress(host, port, "--host", "--haptic-port");
  fd_ = socket(AF_INET, SOCK_DGRAM, 0);
  if (fd_ < 0) throw Error(std::string("haptic bridge: cannot open a UDP socket: ") + std::strerror(errno));
  if (bind(fd_, reinterpret_cast<const sockaddr*>(&a), sizeof a) != 0) {
    const int err = errno;
    close(fd_);
    throw InputError(commandLine(), "--haptic-port", std::to_string(port),
                     std::string("cannot be bound on ") + host + " (" + std::strerror(err) + ")",
                     "a free UDP port, or 0 for any free one");
  }
  socklen_t len = sizeof a;
  getsockname(fd_, reinterpret_cast<sockaddr*>(&a), &len);
  port_ = ntohs(a.sin_port);
  timeval timeout{0, 100000};  // the thread looks at the stop flag every 0.1 s
  setsockopt(fd_, SOL_SOCKET, SO_RCVTIMEO, &timeout, sizeof timeout);
}

HapticServer::~HapticServer() {
  stop();
  if (fd_ >= 0) close(fd_);
}

void HapticServer::start() {
  if (running_.exchange(true)) return;
  thread_ = std::thread([this] { run(); });
}

void HapticServer::stop() {
  running_ = false;
  if (thread_.joinable()) thread_.join();
}

// The latest state, or the session's refusal of a pose since the last answer (the message
// without its "<session>: " location, cut to the packet's 55 bytes).
haptic::Bytes HapticServer::answerTo(const haptic::PosePacket& pose) {
  std::string message;
  if (!live_.refusedSince(sessionRefusals_, message)) return haptic::encode(stateFor(live_.latest(), pose));
  const std::string location = "<session>: ";
  if (message.starts_with(location)) message.erase(0, location.size());
  return haptic::encode(haptic::ErrorPacket{pose.sequence, haptic::ErrorCode::Refused, 0, message});
}

void HapticServer::run() {
  std::array<std::uint8_t, 512> buffer{};
  while (running_) {
    sockaddr_in from{};
    socklen_t len = sizeof from;
    const ssize_t n = recvfrom(fd_, buffer.data(), buffer.size(), 0, reinterpret_cast<sockaddr*>(&from), &len);
    if (n < 0) continue;  // timeout or interruption: look at the stop flag
    const haptic::Decoded d = haptic::decode({buffer.data(), static_cast<std::size_t>(n)});
    haptic::Bytes reply;
    if (d.error) {
      reply = haptic::encode(*d.error);
      ++refused_;
    } else if (d.packet && std::holds_alternative<haptic::PosePacket>(*d.packet)) {
      const auto& pose = std::get<haptic::PosePacket>(*d.packet);
      if (pose.flags & haptic::kPoseReset) live_.reset();
      live_.setTarget(pose.pose);
      reply = answerTo(pose);
      ++answered_;
    } else if (d.packet) {
      reply = haptic::encode(haptic::ErrorPacket{0, haptic::ErrorCode::Type, 0, "a server takes pose packets (type 1)"});
      ++refused_;
    } else {
      continue;  // not this protocol: no answer
    }
    sendto(fd_, reply.data(), reply.size(), 0, reinterpret_cast<const sockaddr*>(&from), len);
  }
}

}  // namespace needlesim::live
