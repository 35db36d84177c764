// The host emulation of the CUDA MPM back-end (mpm_emulation.cpp): the
// plugin's kernels run serially on the host behind the same C interface.
#pragma once

#include "needlesim/engines/mpm/cuda/mpm_device_abi.h"

namespace needlesim::mpm {
const NsMpmBackend* emulationBackend();
}  // namespace needlesim::mpm
