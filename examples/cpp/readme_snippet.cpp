#include <cstdio>
#include <needlesim/needlesim.hpp>
namespace api = needlesim::api;

int main() {  // from the repository's folder
  auto s = api::Scenario::fromFile("examples/gelatin_18G_3mms.yaml");
  double f = api::run(s.with("insertion.profile[0].insert.speed", "5 mm/s")).value("exit_force").value;  // N
  api::Session haptic(s);           // lumped, realtime2d or realtime3d, stepped from your loop
  double force = 0.0;               // N
  for (int k = 1; k <= 2000; ++k)   // 10 mm at 5 mm/s, 1 kHz: step(tip depth [m], dt [s])
    force = haptic.step(k * 5e-6, 1e-3).axial_force;
  std::printf("exit force at 5 mm/s: %.4f N; axial force at 10 mm: %.4f N\n", f, force);
}
