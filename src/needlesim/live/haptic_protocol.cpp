#include "needlesim/live/haptic_protocol.hpp"

#include <bit>
#include <cmath>
#include <cstring>

#include <fmt/format.h>

namespace needlesim::live::haptic {

namespace {

static_assert(std::endian::native == std::endian::little, "the haptic protocol writes little-endian values");

class Writer {
 public:
  explicit Writer(std::size_t size) : bytes_(size, 0) {}
  template <class T>
  Writer& put(T value) {
    std::memcpy(bytes_.data() + at_, &value, sizeof(T));
    at_ += sizeof(T);
    return *this;
  }
  Writer& header(Type type, std::uint32_t sequence) {
    return put(kMagic).put(kVersion).put(static_cast<std::uint16_t>(type)).put(sequence);
  }
  Bytes done() { return std::move(bytes_); }

 private:
  Bytes bytes_;
  std::size_t at_ = 0;
};

class Reader {
 public:
  explicit Reader(std::span<const std::uint8_t> b) : bytes_(b) {}
  template <class T>
  T get() {
    T v;
    std::memcpy(&v, bytes_.data() + at_, sizeof(T));
    at_ += sizeof(T);
    return v;
  }

 private:
  std::span<const std::uint8_t> bytes_;
  std::size_t at_ = 0;
};

ErrorPacket refusal(std::uint32_t sequence, ErrorCode code, std::string message) {
  return ErrorPacket{sequence, code, 0, std::move(message)};
}

std::size_t sizeOf(Type t) { return t == Type::Pose ? kPoseSize : t == Type::State ? kStateSize : kErrorSize; }

PosePacket readPose(Reader& r, std::uint32_t sequence) {
  PosePacket p;
  p.sequence = sequence;
  p.flags = r.get<std::uint32_t>();
  p.clientTimeNs = r.get<std::uint64_t>();
  p.pose = Pose{r.get<double>(), r.get<double>(), r.get<double>(), r.get<double>(), r.get<double>()};
  return p;
}

StatePacket readState(Reader& r, std::uint32_t sequence) {
  StatePacket s;
  s.sequence = sequence;
  s.phase = r.get<std::uint32_t>();
  s.clientTimeNs = r.get<std::uint64_t>();
  s.step = r.get<std::uint64_t>();
  s.time = r.get<double>();
  s.depth = r.get<double>();
  for (double& f : s.force) f = r.get<double>();
  for (double& t : s.torque) t = r.get<double>();
  s.axialForce = r.get<double>();
  s.frictionForce = r.get<double>();
  s.tipDeflection = r.get<double>();
  s.stateAge = r.get<double>();
  return s;
}

ErrorPacket readError(Reader& r, std::uint32_t sequence, std::span<const std::uint8_t> d) {
  ErrorPacket e;
  e.sequence = sequence;
  e.code = static_cast<ErrorCode>(r.get<std::uint32_t>());
  e.clientTimeNs = r.get<std::uint64_t>();
  const char* text = reinterpret_cast<const char*>(d.data() + 24);
  e.message.assign(text, strnlen(text, kErrorSize - 24));
  return e;
}

bool finite(const Pose& p) {
  return std::isfinite(p.depth) && std::isfinite(p.lateral) && std::isfinite(p.rotation) && std::isfinite(p.tilt) &&
         std::isfinite(p.roll);
}

}  // namespace

Bytes encode(const PosePacket& p) {
  return Writer(kPoseSize)
      .header(Type::Pose, p.sequence)
      .put(p.flags)
      .put(p.clientTimeNs)
      .put(p.pose.depth)
      .put(p.pose.lateral)
      .put(p.pose.rotation)
      .put(p.pose.tilt)
      .put(p.pose.roll)
      .done();
}

Bytes encode(const StatePacket& s) {
  Writer w(kStateSize);
  w.header(Type::State, s.sequence).put(s.phase).put(s.clientTimeNs).put(s.step).put(s.time).put(s.depth);
  for (double f : s.force) w.put(f);
  for (double t : s.torque) w.put(t);
  return w.put(s.axialForce).put(s.frictionForce).put(s.tipDeflection).put(s.stateAge).done();
}

Bytes encode(const ErrorPacket& e) {
  Bytes b = Writer(kErrorSize).header(Type::Error, e.sequence).put(static_cast<std::uint32_t>(e.code)).put(e.clientTimeNs).done();
  std::memcpy(b.data() + 24, e.message.data(), std::min<std::size_t>(e.message.size(), kErrorSize - 25));
  return b;
}

Decoded decode(std::span<const std::uint8_t> d) {
  if (d.size() < 16) return {};
  Reader r(d);
  if (r.get<std::uint32_t>() != kMagic) return {};
  const auto version = r.get<std::uint16_t>();
  const auto type = static_cast<Type>(r.get<std::uint16_t>());
  const auto sequence = r.get<std::uint32_t>();
  if (version != kVersion)
    return {{}, refusal(sequence, ErrorCode::Version, fmt::format("version {} not supported; this server speaks 1", version))};
  if (type != Type::Pose && type != Type::State && type != Type::Error)
    return {{}, refusal(sequence, ErrorCode::Type, fmt::format("unknown packet type {}", static_cast<int>(type)))};
  if (d.size() != sizeOf(type))
    return {{}, refusal(sequence, ErrorCode::Size, fmt::format("{} bytes; type {} has {}", d.size(), static_cast<int>(type), sizeOf(type)))};
  if (type == Type::State) return {readState(r, sequence), {}};
  if (type == Type::Error) return {readError(r, sequence, d), {}};
  PosePacket p = readPose(r, sequence);
  if (p.flags & ~kPoseFlags)
    return {{}, refusal(sequence, ErrorCode::Value, fmt::format("flags 0x{:x}: only bit 0 (reset) is defined", p.flags))};
  if (!finite(p.pose)) return {{}, refusal(sequence, ErrorCode::Value, "a pose value is not a finite number")};
  return {p, {}};
}

}  // namespace needlesim::live::haptic
