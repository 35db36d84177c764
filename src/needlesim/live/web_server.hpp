#pragma once
// The trainer's web server (cpp-httplib): one page (web/index.html, web/trainer.js,
// three.js, Chart.js, all compiled in) and a small JSON API over a LiveSession:
//   GET  /api/info            engine, controls, limits, the tissue surface (once)
//   GET  /api/frame?since=N   latest state, surface field, needle, force samples from N on
//   POST /api/drive           held keys/buttons {"insert":1,"rotate":0,...} in [-1, 1]
//   POST /api/flip            bevel half a turn;  POST /api/reset   start over
//   POST /api/stop            stop the server (as Ctrl-C; a recording is written)
// POSTs must say Content-Type: application/json (else 415), which keeps other sites out.
#include <functional>
#include <memory>
#include <string>

#include <nlohmann/json.hpp>

#include "needlesim/live/live_session.hpp"

namespace needlesim::live {

struct WebInfo {
  std::string scenarioName;
  std::string recordFolder;  // "" when not recording
  int hapticPort = -1;       // -1 when no haptic bridge
};

class WebServer {
 public:
  WebServer(LiveSession& live, WebInfo info);
  ~WebServer();
  // Binds host:port (0: any free port); InputError naming --port when it cannot.
  int bind(const std::string& host, int port);
  // Serves until stop() (from any thread) or POST /api/stop.
  void serve();
  void stop();
  void onStopRequest(std::function<void()> f) { stopRequest_ = std::move(f); }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  std::function<void()> stopRequest_;
};

// The JSON documents of the API, for the server and tests.
nlohmann::json infoJson(const LiveSession& live, const WebInfo& info);
nlohmann::json frameJson(const LiveSession& live, std::size_t since);
// A drive from POST /api/drive's body; InputError for text that is not such an object.
Drive driveFromJson(const std::string& body);

}  // namespace needlesim::live
