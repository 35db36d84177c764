// `needlesim serve [FILE]`: the interactive trainer (a live session, its web page and
// the haptic bridge); `needlesim replay DIR`: a recorded session through a fresh session.
#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <chrono>
#include <cstdio>
#include <optional>
#include <thread>

#include "commands.hpp"
#include "needlesim/core/error.hpp"
#include "needlesim/core/progress.hpp"
#include "needlesim/results/results_folder.hpp"
#include "needlesim/live/haptic_server.hpp"
#include "needlesim/live/live_session.hpp"
#include "needlesim/live/net_address.hpp"
#include "needlesim/live/stop_signals.hpp"
#include "needlesim/live/web_server.hpp"

namespace needlesim::app {

namespace {
namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

struct ServeArgs {
  std::string file;
  std::string host = "127.0.0.1";
  int port = 8080;
  int hapticPort = -1;
  std::string record;
  bool overwrite = false;
  double dtMs = 1.0;
  double speedMmPerS = 5.0;
};

api::Scenario readScenario(const std::string& file) {
  return file.empty() ? api::Scenario::builtIn() : api::Scenario::fromFile(file);
}

fs::path recordTarget(const ServeArgs& args) {
  if (args.record.empty()) return {};
  const fs::path chosen = io::outputPath(args.record, "--record", commandLine());
  return io::resolveResultsTarget(chosen, "--record", commandLine(), args.overwrite);
}

live::LiveSettings settingsFor(const ServeArgs& args) {
  if (!(args.dtMs > 0.0 && args.dtMs <= 100.0))
    throw InputError(commandLine(), "--dt", fmt::format("{}", args.dtMs), "is not a physics step", "0 < dt <= 100 (ms)");
  if (!(args.speedMmPerS > 0.0 && args.speedMmPerS <= 100.0))
    throw InputError(commandLine(), "--speed", fmt::format("{}", args.speedMmPerS), "is not an insertion speed", "0 < speed <= 100 (mm/s)");
  live::LiveSettings s;
  s.dt = 1e-3 * args.dtMs;
  s.record = !args.record.empty();
  s.limits.insertSpeed = 1e-3 * args.speedMmPerS;
  s.limits.maxDepth = 0.0;  // from the scenario
  s.fieldEvery = std::max(1, static_cast<int>(0.016 / s.dt));
  s.sampleEvery = std::max(1, static_cast<int>(0.01 / s.dt));
  return s;
}

// Stops the web server once Ctrl-C, SIGTERM or POST /api/stop asked for it.
class StopWatcher {
 public:
  explicit StopWatcher(live::WebServer& web) : thread_([this, &web] {
      while (!stopRequested() && !asked_) std::this_thread::sleep_for(std::chrono::milliseconds(50));
      live::markStopping();
      while (!web.served()) {  // until serve() returned: a stop before it listened is lost
        web.stop();
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
      }
    }) {}
  ~StopWatcher() {
    asked_ = true;
    thread_.join();
  }
  void ask() { asked_ = true; }

 private:
  std::atomic<bool> asked_{false};
  std::thread thread_;
};

// The trainer has no authentication: say so where anyone on the network may reach it.
void warnIfReachable(const ServeArgs& args) {
  live::socketAddress(args.host, 0, "--host", "--port");  // InputError for a host that is no IPv4 address
  if (live::isLoopback(args.host)) return;
  fmt::print(stderr,
             "warning: --host {} serves the trainer beyond this machine WITHOUT AUTHENTICATION: anyone who can reach "
             "its port{} can watch, drive, reset and stop the session. Use --host 127.0.0.1 (the default) unless every "
             "machine on this network is trusted.\n",
             args.host, args.hapticPort >= 0 ? " or the haptic bridge's" : "");
  std::fflush(stderr);
}

void printStarted(const ServeArgs& args, const live::LiveSession& session, int port, const live::HapticServer* haptic,
                  const fs::path& target) {
  fmt::print("needlesim serve: '{}' with engine '{}', physics every {} ms\n", session.scenario().name(), session.engine(), args.dtMs);
  fmt::print("trainer: http://{}:{}/\n", args.host, port);
  if (haptic) fmt::print("haptic bridge: udp://{}:{} (docs/haptic-protocol.md, version 1)\n", args.host, haptic->port());
  fmt::print("Ctrl-C stops{}\n", target.empty() ? "" : " and writes the recording to " + target.string());
  std::fflush(stdout);
}

void printStopped(const ServeArgs& args, const live::LiveSession& session, double wall, const live::HapticServer* haptic) {
  const live::LatestState last = session.latest();
  fmt::print("stopped: {} physics steps in {:.1f} s ({:.0f} steps/s, target {:.0f}; a step took {:.0f} us on average)",
             last.step, wall, static_cast<double>(last.step) / wall, 1e3 / args.dtMs, 1e6 * session.meanStepCost());
  if (haptic) fmt::print("; haptic packets answered {}, refused {}", haptic->answered(), haptic->refused());
  fmt::print("\n");
  std::fflush(stdout);
}

// Writes the recording however the stop came (a further signal meanwhile does not end the
// process: stop_signals.hpp); a write that fails says so and names the folder.
void writeSessionRecording(const ServeArgs& args, const api::Scenario& scenario, const live::LiveSession& session,
                           const fs::path& target, double wall) {
  const std::size_t steps = session.log().size();
  try {
    live::writeRecording(scenario, session.log(), target, args.overwrite, wall,
                         fmt::format("live session of needlesim serve: {} steps of {} ms, replay with needlesim replay", steps, args.dtMs));
  } catch (const std::exception& e) {
    throw Error(fmt::format("the recording of {} steps could not be written to {}: {}", steps, target.string(), e.what()));
  }
  fmt::print("recording: {}/ (summary.json, commands.csv, forces.csv, report.html){}\n", target.string(),
             live::signalsWhileStopping() > 0 ? ", written despite the further stop signal" : "");
}

void serveCommand(const ServeArgs& args) {
  const api::Scenario scenario = readScenario(args.file);
  const fs::path target = recordTarget(args);
  live::LiveSession session(scenario, settingsFor(args));
  warnIfReachable(args);
  std::optional<live::HapticServer> haptic;
  if (args.hapticPort >= 0) haptic.emplace(session, args.host, args.hapticPort);
  live::WebServer web(session, {scenario.name(), target.string(), haptic ? haptic->port() : -1});
  const int port = web.bind(args.host, args.port);
  live::installServeStopHandlers(target.string());
  session.start();
  if (haptic) haptic->start();
  const auto started = Clock::now();
  printStarted(args, session, port, haptic ? &*haptic : nullptr, target);
  {
    StopWatcher watcher(web);
    web.onStopRequest([&watcher] { watcher.ask(); });
    web.serve();
  }
  if (haptic) haptic->stop();
  session.stop();
  const double wall = std::chrono::duration<double>(Clock::now() - started).count();
  printStopped(args, session, wall, haptic ? &*haptic : nullptr);
  clearStopRequest();
  if (!target.empty()) writeSessionRecording(args, scenario, session, target, wall);
}

void replayCommand(const std::string& folder, std::string out, bool overwrite) {
  if (!io::isResultsFolder(folder) || !fs::exists(fs::path(folder) / "commands.csv"))
    throw InputError(commandLine(), "recording", folder, "is not a recording of needlesim serve --record",
                     "a folder holding summary.json and commands.csv");
  const fs::path chosen = out.empty() ? fs::path(folder + "-replay") : io::outputPath(out, "--out", commandLine());
  const fs::path target = io::resolveResultsTarget(chosen, out.empty() ? "" : "--out", commandLine(), overwrite);
  const auto started = Clock::now();
  api::Scenario scenario = api::Scenario::builtIn();
  const live::StepLog log = live::replay(folder, scenario);
  const double difference = live::largestDifference(log.forcesTable(scenario.engine() != "lumped"), fs::path(folder) / "forces.csv");
  live::writeRecording(scenario, log, target, overwrite, std::chrono::duration<double>(Clock::now() - started).count(),
                       "replay of the recording " + folder);
  fmt::print("replayed {} steps of {}: {}/\nlargest difference from the recorded forces.csv: {:.3g}\n", log.size(), folder,
             target.string(), difference);
  if (!(difference <= 1e-6))
    throw SolverError(fmt::format("the replay differs from the recording by {:.3g} (more than 1e-6 in m or N): the "
                                  "recording was made by another build or its files were edited", difference));
}

}  // namespace

void registerServeCommand(CLI::App& app) {
  auto args = std::make_shared<ServeArgs>();
  auto* cmd = app.add_subcommand("serve", "Interactive trainer in the browser: a live session at 1 kHz (docs/serve.md)");
  cmd->add_option("scenario", args->file, "scenario file (realtime2d or lumped); omit for the built-in default");
  cmd->add_option("--host", args->host, "address to listen on (default 127.0.0.1: this machine only)");
  cmd->add_option("--port", args->port, "TCP port of the page (default 8080; 0: any free port)");
  cmd->add_option("--haptic-port", args->hapticPort, "UDP port of the haptic bridge (docs/haptic-protocol.md; 0: any free port)");
  cmd->add_option("--record", args->record, "write the session to this results folder when stopped");
  cmd->add_flag("--overwrite", args->overwrite, "replace an existing needlesim results folder at --record");
  cmd->add_option("--dt", args->dtMs, "physics step in ms (default 1)");
  cmd->add_option("--speed", args->speedMmPerS, "insertion speed of the keys and buttons in mm/s (default 5)");
  cmd->callback([args] { serveCommand(*args); });

  auto replay = std::make_shared<std::tuple<std::string, std::string, bool>>();
  auto* rep = app.add_subcommand("replay", "Re-run a recorded live session through a fresh session and compare its forces");
  rep->add_option("recording", std::get<0>(*replay), "folder written by needlesim serve --record")->required();
  rep->add_option("-o,--out", std::get<1>(*replay), "results folder of the replay (default <recording>-replay)");
  rep->add_flag("--overwrite", std::get<2>(*replay), "replace an existing needlesim results folder there");
  rep->callback([replay] { replayCommand(std::get<0>(*replay), std::get<1>(*replay), std::get<2>(*replay)); });
}

}  // namespace needlesim::app
