#include "needlesim/engines/realtime/run_report.hpp"

#include <algorithm>
#include <cmath>

#include "needlesim/insertion/motion_profile.hpp"
#include "needlesim/results/layer_boundaries.hpp"

namespace needlesim::engines {

RunCadence::RunCadence(double duration_, double dt_, double outputInterval, double fieldInterval)
    : duration(duration_), dt(dt_), steps(static_cast<long long>(std::ceil(duration_ / dt_ - 1e-9))),
      every(outputStride(outputInterval, dt_)),
      fieldEvery(fieldInterval > 0.0 ? std::max(1LL, std::llround(fieldInterval / dt_)) : 0LL) {}

std::vector<double> realtimeMm(std::vector<double> v) {
  for (double& x : v) x *= 1e3;
  return v;
}

void plotAxialForces(const io::Table& f, const Scenario& sc, ResultSink& sink) {
  const auto depth = realtimeMm(f.column("depth"));
  const auto time = f.column("time");
  io::Plot byDepth{"Axial force against tip depth", "tip depth [mm]", "force on the needle [N]", {}};
  io::Plot byTime{"Axial force against time", "time [s]", "force on the needle [N]", {}};
  for (auto* p : {&byDepth, &byTime}) {
    const auto& x = p == &byDepth ? depth : time;
    p->series.push_back({"total", x, f.column("force_total"), false, false});
    p->series.push_back({"stiffness (eq 3.16)", x, f.column("force_stiffness"), false, true});
    p->series.push_back({"cutting (eq 3.24)", x, f.column("force_cutting"), false, true});
    p->series.push_back({"friction (eq 3.23)", x, f.column("force_friction"), false, true});
  }
  results::markLayerBoundaries(byDepth, sc);
  sink.plot(std::move(byDepth));
  sink.plot(std::move(byTime));
}

}  // namespace needlesim::engines
