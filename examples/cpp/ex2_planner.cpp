// Example 2: a planner that evaluates thousands of insertions.
//
// Which entry angle and speed take an 18 G needle through the 55 mm gelatin block of
// examples/gelatin_18G_3mms.yaml with the smallest peak force? Each plan is one lumped
// insertion (seed 003 eq 5.1: cutting + (C_p + b_p v) x length in tissue), stepped at 1 kHz.
//
// Usage: ex2_planner EXAMPLES_FOLDER
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>

#include <needlesim/needlesim.hpp>

namespace api = needlesim::api;

// Peak axial force [N] of one insertion at `speed` [m/s] to `depth` [m] along the needle.
double peakForce(api::Session& session, double speed, double depth, double dt) {
  session.reset();
  double peak = 0.0;
  for (double d = 0.0; d <= depth; d += speed * dt) peak = std::max(peak, session.step(d, dt).axial_force);
  return peak;
}

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s EXAMPLES_FOLDER\n", argv[0]);
    return 2;
  }
  try {
    const auto base = api::Scenario::fromFile(std::filesystem::path(argv[1]) / "gelatin_18G_3mms.yaml");
    const double pi = std::acos(-1.0), dt = 1e-3, block = 55e-3;  // s, m (the block's thickness)
    double best = 1e9, bestAngle = 0.0, bestSpeed = 0.0;
    int plans = 0;
    const auto t0 = std::chrono::steady_clock::now();
    for (int angle = 60; angle <= 90; angle += 1) {  // deg from the tissue surface
      // The entry angle is a scenario field: a varied copy, validated like a file.
      api::Session session(base.with("insertion.entry_angle", std::to_string(angle) + " deg"));
      const double through = block / std::sin(angle * pi / 180.0) + 5e-3;  // m along the needle
      for (double speed = 1e-3; speed <= 10e-3 + 1e-9; speed += 0.25e-3) {  // m/s
        const double peak = peakForce(session, speed, through, dt);
        ++plans;
        if (peak < best) { best = peak; bestAngle = angle; bestSpeed = speed; }
      }
    }
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::printf("plans: %d (31 entry angles x 37 speeds) in %.2f s, %.0f predictions per second\n", plans, seconds,
                plans / seconds);
    std::printf("best plan: entry angle %.0f deg, speed %.2f mm/s, peak force %.6f N\n", bestAngle, bestSpeed * 1e3,
                best);
    return 0;
  } catch (const api::Error& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 2;
  }
}
