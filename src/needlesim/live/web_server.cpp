#include "needlesim/live/web_server.hpp"

#include <httplib.h>

#include <algorithm>
#include <initializer_list>
#include <string>
#include <string_view>

#include "needlesim/core/error.hpp"
#include "needlesim/core/expat_notice.hpp"
#include "needlesim/live/net_address.hpp"

namespace needlesim::embedded {
extern const std::string_view kTrainerHtml, kTrainerJs, kThreeJs, kThreeOrbitControls, kChartJs;
}

namespace needlesim::live {

struct WebServer::Impl {
  LiveSession& live;
  WebInfo info;
  httplib::Server server;
};

namespace {

void serveText(httplib::Server& s, const std::string& path, std::string_view text, const char* type) {
  s.Get(path, [text, type](const httplib::Request&, httplib::Response& res) {
    res.set_content(text.data(), text.size(), type);
    res.set_header("Cache-Control", "no-cache");
  });
}

void sendJson(httplib::Response& res, const nlohmann::json& j) { res.set_content(j.dump(), "application/json"); }

// Commands only as JSON: a browser sends that cross-origin only after a preflight this server
// does not grant, so another site open in the browser cannot drive or stop the session.
void requireJsonPosts(httplib::Server& s) {
  s.set_pre_routing_handler([](const httplib::Request& req, httplib::Response& res) {
    if (req.method != "POST" || req.get_header_value("Content-Type").starts_with("application/json"))
      return httplib::Server::HandlerResponse::Unhandled;
    res.status = 415;
    sendJson(res, {{"error", "commands are JSON: send the header Content-Type: application/json"}});
    return httplib::Server::HandlerResponse::Handled;
  });
}

void routePage(httplib::Server& s) {
  // Debian's three.js files carry no licence notice; the MIT licence asks that copies do.
  static const std::string notice =
      expatNotice("three.js (https://threejs.org), from Debian's libjs-three.", "2010-2017 three.js authors");
  static const std::string three = notice + std::string(embedded::kThreeJs);
  static const std::string orbit = notice + std::string(embedded::kThreeOrbitControls);
  serveText(s, "/", embedded::kTrainerHtml, "text/html; charset=utf-8");
  serveText(s, "/trainer.js", embedded::kTrainerJs, "text/javascript");
  serveText(s, "/three.min.js", three, "text/javascript");
  serveText(s, "/OrbitControls.js", orbit, "text/javascript");
  serveText(s, "/chart.min.js", embedded::kChartJs, "text/javascript");
}

// Runs a handler; a request it refuses (InputError) is answered 400 with the message and field.
template <class Handler>
void answer(httplib::Response& res, Handler handler) {
  try {
    handler();
  } catch (const InputError& e) {
    res.status = 400;
    sendJson(res, {{"error", e.what()}, {"field", e.field()}});
  }
}

// The query parameters a GET takes; InputError naming the first other one.
void requireParams(const httplib::Request& req, std::initializer_list<std::string_view> known, const char* allowed) {
  for (const auto& [key, value] : req.params)
    if (std::find(known.begin(), known.end(), key) == known.end())
      throw InputError(SourceLocation{"GET " + req.path, 0, 0}, printable(key), printable(value),
                       "is not a parameter of this request", allowed);
}

void routeCommands(httplib::Server& s, LiveSession& live, const std::function<void()>& stopRequest) {
  s.Post("/api/drive", [&live](const httplib::Request& req, httplib::Response& res) {
    answer(res, [&] {
      live.setDrive(driveFromJson(req.body));
      sendJson(res, {{"ok", true}});
    });
  });
  s.Post("/api/flip", [&live](const httplib::Request& req, httplib::Response& res) {
    answer(res, [&] {
      requireNoArguments("POST /api/flip", req.body);
      live.flipBevel();
      sendJson(res, {{"ok", true}});
    });
  });
  s.Post("/api/reset", [&live](const httplib::Request& req, httplib::Response& res) {
    answer(res, [&] {
      requireNoArguments("POST /api/reset", req.body);
      live.reset();
      sendJson(res, {{"ok", true}});
    });
  });
  s.Post("/api/stop", [&stopRequest](const httplib::Request& req, httplib::Response& res) {
    answer(res, [&] {
      requireNoArguments("POST /api/stop", req.body);
      sendJson(res, {{"ok", true}});
      if (stopRequest) stopRequest();
    });
  });
}

// Enough workers that idle or half-open connections (a browser keeps up to 6 per site) leave
// some free, and timeouts that close a connection which sends nothing.
void limitConnections(httplib::Server& s) {
  s.new_task_queue = [] { return new httplib::ThreadPool(kHttpWorkers); };
  s.set_read_timeout(kHttpIdleSeconds, 0);
  s.set_write_timeout(kHttpIdleSeconds, 0);
  s.set_keep_alive_timeout(kHttpIdleSeconds);
  s.set_payload_max_length(kHttpMaxBody);  // larger bodies: 413, never read into memory
}

}  // namespace

WebServer::WebServer(LiveSession& live, WebInfo info) : impl_(new Impl{live, std::move(info), {}}) {
  httplib::Server& s = impl_->server;
  limitConnections(s);
  routePage(s);
  requireJsonPosts(s);
  s.Get("/api/info", [this](const httplib::Request& req, httplib::Response& res) {
    answer(res, [&] {
      requireParams(req, {}, "none: GET /api/info takes no parameters");
      sendJson(res, infoJson(impl_->live, impl_->info));
    });
  });
  s.Get("/api/frame", [this](const httplib::Request& req, httplib::Response& res) {
    answer(res, [&] {
      requireParams(req, {"since"}, "since (a sample index)");
      const std::size_t since = req.has_param("since") ? sinceFromQuery(req.get_param_value("since")) : 0;
      sendJson(res, frameJson(impl_->live, since));
    });
  });
  routeCommands(s, impl_->live, stopRequest_);
}

WebServer::~WebServer() = default;

int WebServer::bind(const std::string& host, int port) {
  socketAddress(host, port, "--host", "--port");  // InputError for a host or port that is not one
  const int bound = port == 0 ? impl_->server.bind_to_any_port(host == "localhost" ? "127.0.0.1" : host)
                              : (impl_->server.bind_to_port(host == "localhost" ? "127.0.0.1" : host, port) ? port : -1);
  if (bound <= 0)
    throw InputError(commandLine(), "--port", std::to_string(port), "cannot be bound on " + host + " (in use, or not an address of this machine)",
                     "a free TCP port (0 picks one), or stop the program that holds it");
  return bound;
}

void WebServer::serve() {
  struct Served {
    std::atomic<bool>& flag;
    ~Served() { flag = true; }
  } served{served_};
  impl_->server.listen_after_bind();
}
void WebServer::stop() { impl_->server.stop(); }

}  // namespace needlesim::live
