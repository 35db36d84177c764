#pragma once
// The trainer's web server (cpp-httplib): one page (web/index.html, web/trainer.js,
// three.js, Chart.js, all compiled in) and a small JSON API over a LiveSession:
//   GET  /api/info            engine, controls, limits, the tissue surface, its outline and
//                             inclusions (once)
//   GET  /api/frame?since=N   latest state, surface field, needle, the inclusions' displaced
//                             centres and the targets' miss distance, force samples from N on
//   POST /api/drive           held keys/buttons {"insert":1,"rotate":0,...} in [-1, 1]
//   POST /api/flip            bevel half a turn;  POST /api/reset   start over
//   POST /api/stop            stop the server (as Ctrl-C; a recording is written)
// POSTs must say Content-Type: application/json (else 415), which keeps other sites out.
// A request with an unknown field, parameter or a value of the wrong type is answered 400
// with {"error": message naming the field and what is allowed, "field": its name}.
// Connections are served by kHttpWorkers threads; one that sends nothing for kHttpIdleSeconds
// (between requests, or in the middle of one) is closed, so idle or half-open connections
// cannot hold the page up.
#include <atomic>
#include <functional>
#include <memory>
#include <string>

#include <nlohmann/json.hpp>

#include "needlesim/live/live_session.hpp"

namespace needlesim::live {

inline constexpr int kHttpWorkers = 128;       // connections served at once
inline constexpr int kHttpIdleSeconds = 2;     // read, write and keep-alive timeout
inline constexpr std::size_t kHttpMaxBody = 64 * 1024;  // bytes of a request body

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
  // Stops serve() (a stop asked before serve() listens is lost: call it until served()).
  void stop();
  bool served() const { return served_; }  // serve() has returned
  void onStopRequest(std::function<void()> f) { stopRequest_ = std::move(f); }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  std::function<void()> stopRequest_;
  std::atomic<bool> served_{false};
};

// The JSON documents of the API, for the server and tests.
nlohmann::json infoJson(const LiveSession& live, const WebInfo& info);
nlohmann::json frameJson(const LiveSession& live, std::size_t since);
// A drive from POST /api/drive's body; InputError (its field(): the key) for text that is not
// such an object, a key that is not an axis or a value that is not a number in [-1, 1].
Drive driveFromJson(const std::string& body);
// For the POSTs without arguments (flip, reset, stop): InputError unless the body is empty or {}.
void requireNoArguments(const std::string& request, const std::string& body);
// GET /api/frame's `since`; InputError for text that is not a whole number.
std::size_t sinceFromQuery(const std::string& text);

}  // namespace needlesim::live
