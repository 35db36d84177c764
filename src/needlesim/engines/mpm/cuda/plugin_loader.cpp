// dlopen of the CUDA MPM plugin from fixed places (plugin_loader.hpp).
#include "needlesim/engines/mpm/cuda/plugin_loader.hpp"

#include <dlfcn.h>
#include <fmt/format.h>

#include <cstdlib>
#include <filesystem>
#include <mutex>
#include <system_error>
#include <vector>

namespace needlesim::mpm {
namespace {

std::vector<std::filesystem::path> candidates() {
  namespace fs = std::filesystem;
  if (const char* env = std::getenv("NEEDLESIM_MPM_CUDA_PLUGIN"); env && *env) return {fs::path(env)};
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (ec) return {};
  const fs::path dir = exe.parent_path();
  return {dir / kCudaPluginName, dir / ".." / "lib" / "needlesim" / kCudaPluginName};
}

PluginLoad load() {
  PluginLoad out;
  std::string tried;
  for (const auto& path : candidates()) {
    tried += (tried.empty() ? "" : ", ") + path.string();
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec)) continue;
    void* h = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (!h) {
      const char* e = dlerror();
      out.path = path.string();
      out.problem = fmt::format("{} could not be loaded: {}", path.string(), e ? e : "unknown error");
      return out;
    }
    auto entry = reinterpret_cast<NsMpmBackendEntry>(dlsym(h, "needlesim_mpm_backend"));
    const NsMpmBackend* b = entry ? entry() : nullptr;
    out.path = path.string();
    if (!b) {
      out.problem = fmt::format("{} has no needlesim_mpm_backend entry", path.string());
    } else if (b->abiVersion != NSMPM_ABI_VERSION) {
      out.problem = fmt::format("{} has interface version {}, this needlesim needs {} (rebuild the plugin)",
                                path.string(), b->abiVersion, NSMPM_ABI_VERSION);
    } else {
      out.backend = b;
    }
    return out;  // the handle stays open for the process
  }
  out.path = tried;
  out.problem = fmt::format("{} was not found (looked at: {}; NEEDLESIM_MPM_CUDA_PLUGIN may name the file)",
                            kCudaPluginName, tried.empty() ? "nowhere: the program's directory is unknown" : tried);
  return out;
}

}  // namespace

PluginLoad loadCudaPlugin() {
  static std::mutex m;
  static bool done = false;
  static PluginLoad result;
  std::lock_guard<std::mutex> lock(m);
  if (!done) {
    result = load();
    done = true;
  }
  return result;
}

}  // namespace needlesim::mpm
