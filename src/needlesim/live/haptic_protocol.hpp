#pragma once
// The haptic bridge's wire format, version 1 (docs/haptic-protocol.md): UDP datagrams,
// little-endian, a pose in (64 bytes), the state out (128 bytes) or an error (80 bytes).
#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <variant>

#include "needlesim/live/pose.hpp"

namespace needlesim::live::haptic {

inline constexpr std::uint32_t kMagic = 0x5048534E;  // bytes 'N' 'S' 'H' 'P'
inline constexpr std::uint16_t kVersion = 1;
inline constexpr std::size_t kPoseSize = 64, kStateSize = 128, kErrorSize = 80;

enum class Type : std::uint16_t { Pose = 1, State = 2, Error = 3 };
// Value: a pose value that is not finite, or a flag bit that is not defined (kPoseFlags).
// Refused: the session's step guard refused a pose the needle was moved to since the last
// answer (the needle holds at the last pose the session took).
enum class ErrorCode : std::uint32_t { Version = 1, Size = 2, Type = 3, Value = 4, Refused = 5 };
inline constexpr std::uint32_t kPoseReset = 1u;          // pose flag bit 0
inline constexpr std::uint32_t kPoseFlags = kPoseReset;  // the defined flag bits

struct PosePacket {
  std::uint32_t sequence = 0;
  std::uint32_t flags = 0;           // bit 0: reset the session before this pose
  std::uint64_t clientTimeNs = 0;    // echoed in the reply
  Pose pose;
};

struct StatePacket {
  std::uint32_t sequence = 0;        // of the pose it answers
  std::uint32_t phase = 0;           // 0 outside, 1 pressing, 2 cutting, 3 inside, 4 through
  std::uint64_t clientTimeNs = 0;    // echoed
  std::uint64_t step = 0;            // the physics step the state is from
  double time = 0.0;                 // s, simulated
  double depth = 0.0;                // m, achieved tip depth
  std::array<double, 3> force{};     // N, on the hand (insertion frame: x along the needle, y lateral, z out of plane)
  std::array<double, 3> torque{};    // N m, same frame (0 where the engine has none)
  double axialForce = 0.0;           // N, resistance to insertion (> 0 inserting)
  double frictionForce = 0.0;        // N, its friction part (< 0 retracting)
  double tipDeflection = 0.0;        // m
  double stateAge = 0.0;             // s, from the step to the reply
};

struct ErrorPacket {
  std::uint32_t sequence = 0;
  ErrorCode code = ErrorCode::Version;
  std::uint64_t clientTimeNs = 0;
  std::string message;  // up to 55 bytes are sent
};

using Packet = std::variant<PosePacket, StatePacket, ErrorPacket>;
using Bytes = std::vector<std::uint8_t>;

Bytes encode(const PosePacket& p);
Bytes encode(const StatePacket& p);
Bytes encode(const ErrorPacket& p);

// A datagram as a packet; std::nullopt when it is not this protocol (wrong magic or
// shorter than a header), an ErrorPacket to send back when it is but cannot be taken.
struct Decoded {
  std::optional<Packet> packet;  // the packet, or
  std::optional<ErrorPacket> error;  // what to answer
};
Decoded decode(std::span<const std::uint8_t> datagram);

}  // namespace needlesim::live::haptic
