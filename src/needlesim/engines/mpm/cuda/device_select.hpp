// model.mpm.device: cuda, the refusals before a run starts (what the GPU path
// lacks, no plugin, no device) and the attachment of the plugin to the solver.
#pragma once

#include "needlesim/engines/mpm/mpm_solver.hpp"
#include "needlesim/scenario/scenario.hpp"

namespace needlesim::engines {

// With model.mpm.device: cuda, attaches the CUDA plugin to `solver` (finalized);
// throws InputError naming model.mpm.device and each reason otherwise.
void attachRequestedDevice(mpm::MpmSolver& solver, const Scenario& sc);

}  // namespace needlesim::engines
