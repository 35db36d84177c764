// Example 1: a haptic-style control loop.
//
// A surgical trainer reads the needle's depth from its device 1000 times a second,
// steps the real-time 2D FE model (tissue mesh + flexible needle, seed 003) and sends
// the force back to the hand. Here a steady 3 mm/s push stands in for the hand.
//
// Usage: ex1_haptic_loop EXAMPLES_FOLDER   (the repository's examples/ folder)
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include <needlesim/needlesim.hpp>

namespace api = needlesim::api;

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s EXAMPLES_FOLDER\n", argv[0]);
    return 2;
  }
  try {
    // 10 wt% gelatin, 18 G needle, engine realtime2d (the scenario's own profile is not used:
    // the loop below commands the depth).
    const auto scenario = api::Scenario::fromFile(std::filesystem::path(argv[1]) / "realtime2d/thesis_gelatin_18G_3mms.yaml");
    api::Session session(scenario);

    const double dt = 1e-3;                     // s: 1 kHz
    const double speed = 3e-3;                  // m/s
    const double start = -1e-3, end = 30e-3;    // m, tip depth from the entry face
    const long steps = std::lround((end - start) / (speed * dt));

    double busy = 0.0;  // s spent inside step()
    for (long k = 1; k <= steps; ++k) {
      const double depth = start + speed * dt * static_cast<double>(k);  // what the device reports
      const auto t0 = std::chrono::steady_clock::now();
      const api::State& s = session.step(depth, dt);
      busy += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      if (k % 2000 == 0 || k == steps)  // a display every 2 s of simulated time
        std::printf("t %6.2f s  depth %6.2f mm  axial force %7.4f N  lateral force %8.5f N  "
                    "tip deflection %7.4f mm  (%s)\n",
                    s.time, s.depth * 1e3, s.axial_force, s.lateral_force, s.tip_deflection * 1e3, s.phase.c_str());
    }
    std::printf("steps: %ld at %.0f Hz, mean step time %.1f us\n", steps, 1.0 / dt, busy / steps * 1e6);
    return 0;
  } catch (const api::InputError& e) {
    std::fprintf(stderr, "input error: %s\n", e.what());
    return 2;
  } catch (const api::Error& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 3;
  }
}
