// A haptic device's side of needlesim's haptic bridge (docs/haptic-protocol.md, version 1),
// with nothing but POSIX sockets: no needlesim headers or libraries.
//   needlesim serve scenario.yaml --haptic-port 5700
//   haptic_client [--host 127.0.0.1] [--port 5700] [--depth 0.03] [--seconds 4]
// sends a pose at 1 kHz (in to --depth and back out), reads the force on the hand for each
// and prints the peak force and the round-trip latency percentiles. A device SDK's servo
// loop (OpenHaptics hdScheduler, libnifalcon) would send the stylus pose and render the force.
#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <thread>
#include <vector>

namespace {

constexpr std::uint32_t kMagic = 0x5048534E;  // bytes 'N' 'S' 'H' 'P'
constexpr std::uint16_t kVersion = 1, kPose = 1, kState = 2, kError = 3;
using Clock = std::chrono::steady_clock;

// Little-endian fields at fixed offsets (this example assumes a little-endian host, as x86 and ARM are).
template <class T>
void put(std::uint8_t* b, std::size_t at, T v) { std::memcpy(b + at, &v, sizeof v); }
template <class T>
T get(const std::uint8_t* b, std::size_t at) {
  T v;
  std::memcpy(&v, b + at, sizeof v);
  return v;
}

struct Reply {
  bool ok = false;
  std::uint32_t phase = 0;
  double depth = 0, forceX = 0, axialForce = 0, friction = 0;
  std::string error;
};

struct Options {
  std::string host = "127.0.0.1";
  int port = 5700;
  double depth = 0.03, seconds = 4.0, rate = 1000.0;
};

Options parse(int argc, char** argv) {
  Options o;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string k = argv[i];
    if (k == "--host") o.host = argv[i + 1];
    else if (k == "--port") o.port = std::atoi(argv[i + 1]);
    else if (k == "--depth") o.depth = std::atof(argv[i + 1]);
    else if (k == "--seconds") o.seconds = std::atof(argv[i + 1]);
    else if (k == "--rate") o.rate = std::atof(argv[i + 1]);
  }
  return o;
}

class Client {
 public:
  Client(const std::string& host, int port) : fd_(socket(AF_INET, SOCK_DGRAM, 0)) {
    server_.sin_family = AF_INET;
    server_.sin_port = htons(static_cast<std::uint16_t>(port));
    inet_pton(AF_INET, host.c_str(), &server_.sin_addr);
    timeval timeout{0, 500000};
    setsockopt(fd_, SOL_SOCKET, SO_RCVTIMEO, &timeout, sizeof timeout);
  }
  ~Client() { close(fd_); }

  // One pose (the api::Command fields and the tilt), its answer.
  Reply exchange(double depth, bool reset) {
    std::uint8_t out[64] = {};
    put(out, 0, kMagic);
    put(out, 4, kVersion);
    put(out, 6, kPose);
    put(out, 8, ++sequence_);
    put(out, 12, std::uint32_t(reset ? 1 : 0));
    put(out, 16, std::uint64_t(Clock::now().time_since_epoch().count()));
    put(out, 24, depth);  // lateral, rotation, tilt, roll (32..63) stay 0
    sendto(fd_, out, sizeof out, 0, reinterpret_cast<const sockaddr*>(&server_), sizeof server_);
    std::uint8_t in[512];
    for (;;) {
      const ssize_t n = recv(fd_, in, sizeof in, 0);
      if (n < 16) return {false, 0, 0, 0, 0, 0, "no answer within 0.5 s"};
      if (get<std::uint32_t>(in, 8) != sequence_) continue;  // a late answer to an earlier pose
      if (get<std::uint16_t>(in, 6) == kError)
        return {false, 0, 0, 0, 0, 0, std::string(reinterpret_cast<const char*>(in + 24), strnlen(reinterpret_cast<const char*>(in + 24), 56))};
      if (get<std::uint16_t>(in, 6) != kState || n != 128) return {false, 0, 0, 0, 0, 0, "unexpected packet"};
      return {true, get<std::uint32_t>(in, 12), get<double>(in, 40), get<double>(in, 48), get<double>(in, 96), get<double>(in, 104), ""};
    }
  }

 private:
  int fd_;
  sockaddr_in server_{};
  std::uint32_t sequence_ = 0;
};

double percentile(std::vector<double> v, double p) {
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, static_cast<std::size_t>(p / 100.0 * static_cast<double>(v.size() - 1) + 0.5))];
}

}  // namespace

int main(int argc, char** argv) {
  const Options o = parse(argc, argv);
  Client client(o.host, o.port);
  const int steps = static_cast<int>(o.seconds * o.rate);
  const auto period = std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(1.0 / o.rate));
  std::vector<double> rtt;
  double peak = 0.0, peakDepth = 0.0;
  const auto start = Clock::now();
  for (int i = 0; i < steps; ++i) {
    const double phase = static_cast<double>(i) / std::max(steps - 1, 1);
    const double depth = o.depth * (phase < 0.5 ? 2 * phase : 2 * (1 - phase));
    const auto sent = Clock::now();
    const Reply r = client.exchange(depth, false);
    if (!r.ok) {
      std::fprintf(stderr, "haptic_client: %s\n", r.error.c_str());
      return 1;
    }
    rtt.push_back(std::chrono::duration<double>(Clock::now() - sent).count());
    if (r.axialForce > peak) peak = r.axialForce, peakDepth = r.depth;
    std::this_thread::sleep_until(start + (i + 1) * period);
  }
  std::printf("%d poses at %.0f Hz; peak axial force %.3f N at depth %.2f mm\n", steps, o.rate, peak, peakDepth * 1e3);
  std::printf("round trip: p50 %.0f us, p99 %.0f us, max %.0f us\n", percentile(rtt, 50) * 1e6, percentile(rtt, 99) * 1e6,
              *std::max_element(rtt.begin(), rtt.end()) * 1e6);
  return peak > 0.0 ? 0 : 1;
}
