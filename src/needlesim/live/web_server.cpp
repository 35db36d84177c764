#include "needlesim/live/web_server.hpp"

#include <httplib.h>

#include <string_view>

#include "needlesim/core/error.hpp"
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
  serveText(s, "/", embedded::kTrainerHtml, "text/html; charset=utf-8");
  serveText(s, "/trainer.js", embedded::kTrainerJs, "text/javascript");
  serveText(s, "/three.min.js", embedded::kThreeJs, "text/javascript");
  serveText(s, "/OrbitControls.js", embedded::kThreeOrbitControls, "text/javascript");
  serveText(s, "/chart.min.js", embedded::kChartJs, "text/javascript");
}

}  // namespace

WebServer::WebServer(LiveSession& live, WebInfo info) : impl_(new Impl{live, std::move(info), {}}) {
  httplib::Server& s = impl_->server;
  routePage(s);
  requireJsonPosts(s);
  s.Get("/api/info", [this](const httplib::Request&, httplib::Response& res) { sendJson(res, infoJson(impl_->live, impl_->info)); });
  s.Get("/api/frame", [this](const httplib::Request& req, httplib::Response& res) {
    std::size_t since = 0;
    if (req.has_param("since")) since = std::strtoull(req.get_param_value("since").c_str(), nullptr, 10);
    sendJson(res, frameJson(impl_->live, since));
  });
  s.Post("/api/drive", [this](const httplib::Request& req, httplib::Response& res) {
    try {
      impl_->live.setDrive(driveFromJson(req.body));
      sendJson(res, {{"ok", true}});
    } catch (const InputError& e) {
      res.status = 400;
      sendJson(res, {{"error", e.what()}});
    }
  });
  s.Post("/api/flip", [this](const httplib::Request&, httplib::Response& res) {
    impl_->live.flipBevel();
    sendJson(res, {{"ok", true}});
  });
  s.Post("/api/reset", [this](const httplib::Request&, httplib::Response& res) {
    impl_->live.reset();
    sendJson(res, {{"ok", true}});
  });
  s.Post("/api/stop", [this](const httplib::Request&, httplib::Response& res) {
    sendJson(res, {{"ok", true}});
    if (stopRequest_) stopRequest_();
  });
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

void WebServer::serve() { impl_->server.listen_after_bind(); }
void WebServer::stop() { impl_->server.stop(); }

}  // namespace needlesim::live
