#pragma once
// Each subcommand registers itself on the CLI11 app; main() only dispatches.
namespace CLI {
class App;
}

namespace needlesim::app {
void registerRunCommand(CLI::App& app);
void registerCheckCommand(CLI::App& app);
void registerSchemaCommand(CLI::App& app);
void registerSweepCommand(CLI::App& app);
void registerPlanCommand(CLI::App& app);  // cmd_plan.cpp
void registerServeCommand(CLI::App& app);  // serve and replay (cmd_serve.cpp)
void keepProgramArgs(char** argv);  // for chooseOpenMpWait
void chooseOpenMpWait();            // may start the program again (openmp_wait.cpp)
}  // namespace needlesim::app

// Defined in cmd_fit.cpp (tissue characterisation).
void registerFitCommand(CLI::App& app) __attribute__((weak));
