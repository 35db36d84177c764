// How OpenMP's idle threads wait, chosen before libgomp reads its environment.
//
// By default a waiting thread spins ~300,000 times before it sleeps. When another process keeps
// a core busy (two tests at once on a 2-core machine, a study beside other work), the thread that
// should run next waits for the spinner's time slice at every barrier, and the explicit engine's
// steps (several barriers each) crawl: the 2D block of scripts/imported_block_convergence.sh at
// 0.35 mm took 22-28 s on two idle cores and did not finish the first of its two runs in 180 s
// beside two busy `yes` processes. With GOMP_SPINCOUNT=1000 it took 25-27 s idle and 45-57 s
// beside them (10000: 29 s idle, 57-106 s loaded; OMP_WAIT_POLICY=passive: 35-36 s idle,
// 57-67 s loaded).
//
// libgomp parses its environment in its own constructor, before main(), and the C library resets
// the environment after the program's .preinit_array: the only way to choose is to set the
// variable and start the program again (once: the variable is then set). Starting again costs
// about 0.1 s of CPU (the shared libraries load twice), so only the commands that run an OpenMP
// engine (EngineInfo::openmp: explicit, mpm) or a sweep do it, having read no more than the
// scenario's model.engine (scenario::engineNamedIn), before its meshes or any output. A user's own
// OMP_WAIT_POLICY or GOMP_SPINCOUNT is kept; summary.json records which ran.
#include <unistd.h>

#include <cstdlib>

#include "commands.hpp"

namespace needlesim::app {

namespace {
char** programArgs = nullptr;
}

void keepProgramArgs(char** argv) { programArgs = argv; }

void chooseOpenMpWait() {
  if (programArgs == nullptr) return;
  if (std::getenv("OMP_WAIT_POLICY") != nullptr || std::getenv("GOMP_SPINCOUNT") != nullptr) return;
  if (setenv("GOMP_SPINCOUNT", "1000", 0) != 0) return;
  execv("/proc/self/exe", programArgs);  // returns only when it fails: then run on with libgomp's default
}

}  // namespace needlesim::app
