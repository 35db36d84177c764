// model.mpm.device: cuda (device_select.hpp).
#include "needlesim/engines/mpm/cuda/device_select.hpp"

#include <fmt/format.h>

#include "needlesim/core/error.hpp"
#include "needlesim/engines/mpm/cuda/plugin_loader.hpp"

namespace needlesim::engines {

void attachRequestedDevice(mpm::MpmSolver& solver, const Scenario& sc) {
  const MpmModelSpec& m = sc.model.mpm;
  if (!m.cuda) return;
  const std::string field = "model.mpm.device";
  const auto missing = solver.deviceUnsupported();
  if (!missing.empty()) {
    std::string list;
    for (const auto& s : missing) list += (list.empty() ? "" : "; ") + s;
    throw InputError(sc.where(field), field, "cuda", "mpm: the GPU path does not implement: " + list,
                     "cpu, or a scenario without these (the needle contact the GPU path runs: model.mpm.contact: grid with "
                     "parting: none)");
  }
  const mpm::PluginLoad plugin = mpm::loadCudaPlugin();
  if (!plugin.backend)
    throw InputError(sc.where(field), field, "cuda", "mpm: no CUDA plugin: " + plugin.problem,
                     "cpu, or a needlesim built with nvcc (its libneedlesim_mpm_cuda.so beside the program)");
  char msg[512] = "";
  if (plugin.backend->probe(msg, sizeof msg) < 1)
    throw InputError(sc.where(field), field, "cuda", fmt::format("mpm: no usable CUDA device ({})", msg), "cpu");
  solver.attachDevice(plugin.backend, NSMPM_KERNEL_SORTED);
}

}  // namespace needlesim::engines
