// Finding and loading the CUDA MPM plugin (libneedlesim_mpm_cuda.so) with
// dlopen: from the environment variable NEEDLESIM_MPM_CUDA_PLUGIN (a file),
// else the directory of the running program, else ../lib/needlesim/ beside
// it. Never a path from a scenario.
#pragma once

#include <string>

#include "needlesim/engines/mpm/cuda/mpm_device_abi.h"

namespace needlesim::mpm {

inline constexpr const char* kCudaPluginName = "libneedlesim_mpm_cuda.so";

struct PluginLoad {
  const NsMpmBackend* backend = nullptr;  // null: not loaded, see problem
  std::string path;                       // the file loaded, or the places looked at
  std::string problem;
};

// The plugin's back-end table (loaded once per process and kept).
PluginLoad loadCudaPlugin();

}  // namespace needlesim::mpm
