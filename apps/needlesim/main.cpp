// needlesim command line: run, check, schema, fit. Errors in user input exit
// with code 2 and a message naming file, line, field and what is allowed;
// a solver that cannot go on exits with 3.
#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <cstdio>
#include <cstdlib>

#include "commands.hpp"
#include "needlesim/core/error.hpp"
#include "needlesim/core/progress.hpp"
#include "needlesim/core/version.hpp"
#include "needlesim/needlesim.hpp"

int main(int argc, char** argv) {
  needlesim::app::keepProgramArgs(argv);  // run and sweep may start again (openmp_wait.cpp)
  CLI::App app{"needlesim: needle insertion into soft tissue — forces, deflection, steering, deformation, fracture"};
  app.set_version_flag("--version", fmt::format("needlesim {} ({})", needlesim::kVersion, needlesim::kGitRevision));
  app.require_subcommand(1);
  needlesim::app::registerRunCommand(app);
  needlesim::app::registerCheckCommand(app);
  needlesim::app::registerSchemaCommand(app);
  needlesim::app::registerSweepCommand(app);
  needlesim::app::registerPlanCommand(app);
  needlesim::app::registerServeCommand(app);
  if (registerFitCommand) registerFitCommand(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::RuntimeError& e) {  // a command's own exit status (plan: 4, no plan)
    return e.get_exit_code();
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);  // prints the help, the version or what is wrong with the arguments
    return code == 0 ? 0 : 2;      // bad arguments are bad input: exit 2, as for a scenario
  } catch (const needlesim::RunInterrupted& e) {
    fmt::print(stderr, "stopped: {}\n", e.what());
    return e.signal() > 0 ? 128 + e.signal() : 1;  // 130 for Ctrl-C, 143 for SIGTERM, as a shell reports them
  } catch (const needlesim::InputError& e) {
    fmt::print(stderr, "error: {}\n", e.what());
    return 2;
  } catch (const needlesim::SolverError& e) {
    fmt::print(stderr, "solver stopped: {}\n", e.what());
    return 3;
  } catch (const needlesim::api::InputError& e) {  // the public API's errors (live sessions)
    fmt::print(stderr, "error: {}\n", e.what());
    return 2;
  } catch (const needlesim::api::SolverError& e) {
    fmt::print(stderr, "solver stopped: {}\n", e.what());
    return 3;
  } catch (const std::exception& e) {
    fmt::print(stderr, "error: {}\n", e.what());
    return 1;
  }
  return 0;
}
