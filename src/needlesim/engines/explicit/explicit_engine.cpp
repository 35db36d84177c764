#include "needlesim/engines/explicit/explicit_engine.hpp"

#include <algorithm>
#include <chrono>
#include <optional>

#include <fmt/format.h>

#include "needlesim/core/progress.hpp"
#include "needlesim/engines/memory_sink.hpp"
#include "needlesim/engines/explicit/bonded_tip.hpp"
#include "needlesim/engines/explicit/explicit_run.hpp"
#include "needlesim/engines/explicit/path_needle.hpp"
#include "needlesim/engines/run_cost.hpp"

#ifdef _OPENMP
#include <omp.h>
#endif

namespace needlesim::explicit_fe {

// The needle's pose at time t for the step of length dt: the tip on the axis at the profile's depth,
// the bevel turned by the profile's rotation (needle_motion.hpp: 3D spins the surface; a 2D
// plane-strain model can only show the bevel on one side or the other), a deformable needle's
// deflection on top.
void ExplicitRun::poseNeedle(double t, double dt) {
  auto* n = solver_->needle();
  const auto ms = motion_.at(t + 0.5 * dt);
  const auto m0 = motion_.at(t);
  n->pose.tip = frame_.onAxis(m0.depth);
  n->velocity = ms.velocity;
  const double roll = m0.axial_angle - frame_.bevelOrientation;
  n->pose.bevelSide = dim_ == 2 ? Eigen::Vector3d(frame_.bevelSign(roll) * frame_.lateral) : frame_.bevelSide(roll);
  n->spinRate = dim_ == 3 ? ms.axial_rate : 0.0;
  n->pose.axis = frame_.axial;
  if (n->path) placeOnPath(*n, m0.depth);
  if (beam_)
    beam_->update(*n, *solver_, n->pose.tip - shape_.length * frame_.axial, frame_.axial, n->pose.bevelSide,
                  thickness_);
}

// A needle that went into the tissue by more than an element without touching a node passed between the
// nodes: its zero force is the mesh's, not the tissue's, so the run stops instead of completing.
void ExplicitRun::requireContact() const {
  const double deepest = sc_.maxDepth(), h = ex_.element_size;
  if (touched_ || !(deepest > h)) return;
  throw SolverError(fmt::format("the needle went {:g} mm into the tissue without touching a tissue node: it passes "
                                "between the nodes of the {:g} mm mesh. Remedy: model.explicit.element_size of at "
                                "most the needle's outer radius ({:g} mm), or pre_cut: true",
                                deepest * 1e3, h * 1e3, shape_.radius * 1e3));
}

void ExplicitRun::run(const RunOptions& options) {
  Progress progress("explicit FE", options.progress);
  const auto t0 = std::chrono::steady_clock::now();
  const double T = duration_;
  const double outDt = sc_.output.interval > 0 ? sc_.output.interval : T / 500.0;
  const double fieldDt = ex_.field_interval > 0 ? ex_.field_interval : T / 20.0;
  try {
    record();
    writeFields();
    double nextOut = outDt, nextField = fieldDt;
    while (solver_->time() < T * (1 - 1e-12)) {
      const double t = solver_->time(), dt = std::min(solver_->timeStep(), T - t);
      poseNeedle(t, dt);
      solver_->advanceTo(std::min(T, t + solver_->timeStep()));
      if (const auto* n = solver_->needle(); n && n->nodesInContact > 0) touched_ = true;
      if (solver_->time() >= nextOut * (1 - 1e-9) || solver_->time() >= T * (1 - 1e-12)) {
        record();
        nextOut += outDt;
        progress.update(solver_->time() / T);
      } else if (stopRequested()) {
        progress.update(solver_->time() / T);  // a stop is seen at the next step, not the next output row
      }
      if (solver_->time() >= nextField * (1 - 1e-9)) {
        writeFields();
        nextField += fieldDt;
      }
    }
    requireContact();
  } catch (const SolverError& e) {
    record();
    finish(std::string("stopped: ") + e.what());
    throw;
  }
  progress.finish();
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  sink_.result("element_updates_per_second", solver_->elementUpdates() / std::max(wall, 1e-9), "1/s",
               "element force evaluations per second of wall time");
  finish("completed");
}

namespace {
// The threads that share the element loops: model.explicit.threads, else OpenMP's default;
// one below 4,000 elements, where the loops run serially (solver.cpp, kParallelMin).
int explicitThreads([[maybe_unused]] const Scenario& sc, int elements) {
  if (elements < 4000) return 1;
#ifdef _OPENMP
  return sc.model.explicit_fe.threads > 0 ? sc.model.explicit_fe.threads : omp_get_max_threads();
#else
  return 1;
#endif
}
}  // namespace

StepPlan ExplicitRun::stepPlan() const {
  StepPlan p;
  p.engine = "explicit";
  p.dt = solver_->timeStep();
  p.dtSetBy = fmt::format("the stable step of the mesh: model.explicit.cfl {:g}, mass_scaling {:g}, elements down to "
                          "{:.3g} mm",
                          ex_.cfl, ex_.mass_scaling, solver_->minElementSize() * 1e3);
  p.dtField = "model.explicit.mass_scaling";
  p.dtValue = fmt::format("{:g}", ex_.mass_scaling);
  p.stepAllowed = massScaledStep(p.dtField, ex_.mass_scaling, p.dt, "a lower model.explicit.cfl or a finer mesh");
  p.adaptive = true;  // the stable step of the deforming mesh
  p.fewerSteps = "a larger model.explicit.mass_scaling or element_size, or a tissue nu further from 0.5";
  p.spacing = solver_->minElementSize();
  p.spacingName = "the smallest element (model.explicit.element_size)";
  p.updatesPerStep = solver_->mesh().elements();
  p.updates = "elements";
  const ElementType type = solver_->mesh().type;
  p.secondsPerUpdate = type == ElementType::Hex8   ? run_cost::kExplicitHex8Element
                       : type == ElementType::Tet4 ? run_cost::kExplicitTet4Element
                                                   : run_cost::kExplicitPlaneElement;
  p.setupSeconds = run_cost::kExplicitSetupPerElement * p.updatesPerStep;
  p.threads = explicitThreads(sc_, solver_->mesh().elements());
  return p;
}

}  // namespace needlesim::explicit_fe

namespace needlesim::engines {

StepPlan explicitStepPlan(const Scenario& sc) {
  if (sc.model.explicit_fe.tip == "bonded") return explicit_fe::bondedTipStepPlan(sc);
  MemorySink discard;
  const BlockingCall setUp("explicit: setting up the mesh and the needle");
  return explicit_fe::ExplicitRun(sc, discard).stepPlan();
}

void runExplicit(const Scenario& sc, ResultSink& sink, const RunOptions& options) {
#ifdef _OPENMP
  if (sc.model.explicit_fe.threads > 0) omp_set_num_threads(sc.model.explicit_fe.threads);
#endif
  if (sc.model.explicit_fe.tip == "bonded") {
    guardAndAnnounce(sc, explicit_fe::bondedTipStepPlan(sc), sink, options);
    return explicit_fe::runBondedTip(sc, sink);
  }
  std::optional<explicit_fe::ExplicitRun> run;
  {
    const BlockingCall setUp("explicit: setting up the mesh and the needle");
    run.emplace(sc, sink);
  }
  guardAndAnnounce(sc, run->stepPlan(), sink, options);
  run->run(options);
}

}  // namespace needlesim::engines
