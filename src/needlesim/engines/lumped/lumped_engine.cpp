#include "needlesim/engines/lumped/lumped_engine.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "needlesim/core/progress.hpp"
#include "needlesim/engines/run_cost.hpp"
#include "needlesim/forces/lumped_model.hpp"
#include "needlesim/insertion/motion_profile.hpp"
#include "needlesim/needle/insertion_frame.hpp"
#include "needlesim/results/forces_table.hpp"
#include "needlesim/results/layer_boundaries.hpp"

namespace needlesim::engines {

// The lumped model finds a puncture, and the layer the tip is in, from the tip
// depth at each step: a step must not carry the tip through much of a layer.
StepPlan lumpedStepPlan(const Scenario& sc) {
  StepPlan p = fixedStepPlan(sc, "lumped");
  p.spacing = sc.tissue.layers.front().thickness;
  for (const auto& L : sc.tissue.layers) p.spacing = std::min(p.spacing, L.thickness);
  p.spacingName = "the thinnest layer";
  p.secondsPerStep = run_cost::kLumpedStep;
  return p;
}

void runLumped(const Scenario& sc, ResultSink& sink, const RunOptions& options) {
  guardAndAnnounce(sc, lumpedStepPlan(sc), sink, options);
  forces::LumpedForceModel model(sc.tissue, sc.needle, sc.insertion.entry_angle, sc.model.lumped.relaxation_time);
  MotionProfile motion(sc.insertion);
  const double dt = sc.model.time_step;
  const auto steps = static_cast<long long>(std::ceil(motion.duration() / dt - 1e-9));
  const long long every =
      outputStride(sc.output.interval, dt);

  // The lumped model is axial (seed 003 section 3.2): force_lateral is 0 by construction and
  // the tip runs along the straight axis of the shared frame.
  const auto frame = needle::InsertionFrame::fromInsertion(sc.insertion);
  results::ForcesTable table(false, {{"force_stiffness", "N"},
                                     {"force_cutting", "N"},
                                     {"force_friction", "N"},
                                     {"contact_length", "m"},
                                     {"phase", "1"},
                                     {"layer", "1"}});
  table.reserve(static_cast<std::size_t>(steps / every + 2));
  Progress progress("lumped", options.progress);

  double peak = 0.0, peakDepth = 0.0, exitForce = NAN, maxFriction = 0.0;
  bool exited = false;
  const double blockEnd = model.layerEnd(model.layerCount() - 1);
  std::vector<double> punctureForces;
  double prevTotal = 0.0, lastInside = 0.0;
  for (long long k = 0; k <= steps; ++k) {
    const double t = std::min(k * dt, motion.duration());
    MotionState m = motion.at(t);
    forces::ForceBreakdown f = model.step(m.depth, m.velocity, dt);
    if (f.punctured_now) punctureForces.push_back(prevTotal);
    prevTotal = f.total();
    if (f.total() > peak) {
      peak = f.total();
      peakDepth = m.depth;
    }
    maxFriction = std::max(maxFriction, f.friction);
    if (!exited && m.depth >= blockEnd && m.velocity > 0.0) {
      exited = true;  // the force just before the tip left the block, cutting included
      exitForce = lastInside;
    }
    if (m.depth < blockEnd) lastInside = f.total();
    if (k % every == 0 || k == steps) {
      const auto tip = frame.onAxis(m.depth);
      table.add({t, m.depth, m.velocity, f.total(), 0.0, tip.x(), tip.y(), tip.z()},
                {f.stiffness, f.cutting, f.friction, f.contact_length, static_cast<double>(f.phase),
                 static_cast<double>(f.layer)});
    }
    if ((k & 1023) == 0) progress.update(static_cast<double>(k) / static_cast<double>(steps + 1));
  }
  progress.finish();

  sink.result("peak_force", peak, "N", "largest total force on the needle base");
  warnZeroForce(sc, peak, sink);
  sink.result("peak_force_depth", peakDepth, "m", "tip depth at the peak force");
  if (exited) sink.result("exit_force", exitForce, "N", "total force as the tip reaches the exit face (full penetration)");
  sink.result("max_friction_force", maxFriction, "N", "largest friction force along the shaft");
  const auto& at = model.punctureDepthsReached();
  sink.result("punctures", static_cast<double>(at.size()), "1", "number of layers punctured");
  for (std::size_t i = 0; i < at.size(); ++i) {
    sink.result(fmt::format("puncture_{}_depth", i + 1), at[i], "m",
                fmt::format("tip depth at puncture of layer {} ({})", i + 1, sc.tissue.layers[i].name));
    sink.result(fmt::format("puncture_{}_force", i + 1), punctureForces[i], "N",
                fmt::format("total force just before puncture of layer {}", i + 1));
  }

  // Plots: force against depth and time, split into components.
  const io::Table& forces = table.table();
  auto depth = forces.column("depth");
  auto time = forces.column("time");
  for (double& d : depth) d *= 1e3;
  auto comp = [&](const std::string& col, const std::string& label, const std::vector<double>& x, bool dashed) {
    return io::PlotSeries{label, x, forces.column(col), false, dashed};
  };
  io::Plot byDepth{"Insertion force against tip depth", "tip depth [mm]", "force on the needle base [N]", {}};
  io::Plot byTime{"Insertion force against time", "time [s]", "force on the needle base [N]", {}};
  for (auto* p : {&byDepth, &byTime}) {
    const auto& x = p == &byDepth ? depth : time;
    p->series.push_back(comp("force_total", "total", x, false));
    p->series.push_back(comp("force_stiffness", "stiffness (eq 3.16)", x, true));
    p->series.push_back(comp("force_cutting", "cutting (eq 3.24)", x, true));
    p->series.push_back(comp("force_friction", "friction (eq 3.23)", x, true));
  }
  results::markLayerBoundaries(byDepth, sc);
  sink.plot(std::move(byDepth));
  sink.plot(std::move(byTime));
  sink.note("Lumped force model of seed 003 section 3.2: pre-puncture stiffness (eq 3.16), constant cutting "
            "(eq 3.24) and modified Karnopp friction along the length in contact (eq 3.23 with the per-length "
            "coefficients of eq 5.1). Interpretations: docs/models/lumped-force.md.");
  sink.table("forces", table.release());
}

}  // namespace needlesim::engines
