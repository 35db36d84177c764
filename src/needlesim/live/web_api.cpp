// The JSON documents of the trainer's API (web_server.hpp).
#include <algorithm>
#include <array>
#include <cmath>
#include <iterator>
#include <utility>

#include "needlesim/core/error.hpp"
#include "needlesim/live/inclusion_readout.hpp"
#include "needlesim/live/web_server.hpp"

namespace needlesim::live {

namespace {

std::vector<float> floats(const std::vector<double>& v) { return {v.begin(), v.end()}; }

nlohmann::json poseJson(const Pose& p) {
  return {{"depth", p.depth}, {"lateral", p.lateral}, {"rotation", p.rotation}, {"tilt", p.tilt}, {"roll", p.roll}};
}

nlohmann::json stateJson(const api::State& s) {
  return {{"time", s.time},           {"depth", s.depth},
          {"axial", s.axial_force},   {"lateral", s.lateral_force},
          {"stiffness", s.stiffness_force}, {"cutting", s.cutting_force},
          {"friction", s.friction_force},   {"deflection", s.tip_deflection},
          {"tip", {s.tip_x, s.tip_y, s.tip_z}}, {"phase", s.phase}};
}

nlohmann::json orNull(const std::optional<double>& v) { return v ? nlohmann::json(*v) : nlohmann::json(nullptr); }

// The tissue's outline: its bounds (the surface's), and the imported geometry's file when the
// surface is an imported tissue's (a viewer then outlines the surface itself, not a box).
nlohmann::json outlineJson(const api::Surface& surface) {
  std::array<double, 3> lo{0.0, 0.0, 0.0}, hi{0.0, 0.0, 0.0};
  for (std::size_t i = 0; i + 2 < surface.vertices.size(); i += 3)
    for (std::size_t c = 0; c < 3; ++c) {
      lo[c] = i == 0 ? surface.vertices[i + c] : std::min(lo[c], surface.vertices[i + c]);
      hi[c] = i == 0 ? surface.vertices[i + c] : std::max(hi[c], surface.vertices[i + c]);
    }
  return {{"kind", surface.geometry.empty() ? "block" : "imported"},
          {"file", surface.geometry.empty() ? nlohmann::json(nullptr) : nlohmann::json(surface.geometry)},
          {"lo", lo}, {"hi", hi}};
}

nlohmann::json inclusionsJson(const std::vector<api::Inclusion>& inclusions) {
  nlohmann::json out = nlohmann::json::array();
  for (const api::Inclusion& I : inclusions)
    out.push_back({{"name", I.name}, {"shape", I.shape}, {"centre", {I.x, I.y, I.z}}, {"radius", I.radius},
                   {"target", I.target}, {"region", I.region}});
  return out;
}

// Before the viewer thread's first field the frame's needle is not yet of a stepped state: no
// miss then.
nlohmann::json readoutsJson(const LiveSession& live, const Frame& f) {
  nlohmann::json out = nlohmann::json::array();
  for (const InclusionReadout& r : inclusionReadouts(live.inclusions(), f.field, f.fields > 0 ? f.needle : std::vector<double>{}))
    out.push_back({{"centre", r.centre}, {"miss", orNull(r.miss)}, {"missFromAxis", orNull(r.missFromAxis)}});
  return out;
}

}  // namespace

nlohmann::json infoJson(const LiveSession& live, const WebInfo& info) {
  const Controls& c = live.controls();
  const MotionLimits& l = live.settings().limits;
  return {{"needlesim", api::version()},
          {"scenario", info.scenarioName},
          {"engine", live.engine()},
          {"dt", live.settings().dt},
          {"controls", {{"lateral", c.lateral}, {"rotation", c.rotation}, {"tilt", c.tilt}, {"roll", c.roll}}},
          {"limits", {{"insertSpeed", l.insertSpeed}, {"minDepth", l.minDepth}, {"maxDepth", l.maxDepth}}},
          {"surface", {{"vertices", floats(live.surface().vertices)}, {"triangles", live.surface().triangles}}},
          {"outline", outlineJson(live.surface())},
          {"inclusions", inclusionsJson(live.inclusions())},
          {"record", info.recordFolder.empty() ? nlohmann::json(nullptr) : nlohmann::json(info.recordFolder)},
          {"hapticPort", info.hapticPort < 0 ? nlohmann::json(nullptr) : nlohmann::json(info.hapticPort)},
          {"phases", {kPhases[0], kPhases[1], kPhases[2], kPhases[3], kPhases[4]}}};
}

nlohmann::json frameJson(const LiveSession& live, std::size_t since) {
  Frame f;
  live.frame(f);
  std::size_t total = 0;
  nlohmann::json samples = nlohmann::json::array();
  for (const Sample& s : live.samples(since, total))
    samples.push_back({s.time, s.depth, s.axial, s.friction, s.lateral, s.deflection, s.phase});
  return {{"step", f.latest.step},
          {"rate", f.rate},
          {"overruns", f.overruns},
          {"stepCost", f.stepCost},
          {"stepMaxCost", f.stepMaxCost},
          {"pose", poseJson(f.latest.pose)},
          {"state", stateJson(f.latest.state)},
          {"refusals", f.refusals},
          {"refusal", f.refusal.empty() ? nlohmann::json(nullptr) : nlohmann::json(f.refusal)},
          {"puncture", f.punctureDepth < 0.0 ? nlohmann::json(nullptr) : nlohmann::json(f.punctureDepth)},
          {"field", {{"displacement", floats(f.field.displacement)}, {"scalar", floats(f.field.scalar)},
                     {"name", f.field.scalarName}, {"unit", f.field.scalarUnit},
                     {"step", f.fieldStep}, {"cost", f.fieldCost}}},
          {"needle", floats(f.needle)},
          {"inclusions", readoutsJson(live, f)},
          {"samples", std::move(samples)},
          {"next", total}};
}

namespace {

constexpr const char* kDriveAllowed = "{\"insert\": -1..1, \"lateral\": ..., \"rotate\": ..., \"tilt\": ..., \"roll\": ...}";

const std::pair<const char*, double Drive::*> kDriveAxes[] = {
    {"insert", &Drive::insert}, {"lateral", &Drive::lateral}, {"rotate", &Drive::rotate},
    {"tilt", &Drive::tilt},     {"roll", &Drive::roll}};

// A JSON value as echoed in a message: scalars as written, arrays and objects by their kind
// (never dumped: a deeply nested value would take a deep recursion).
std::string describe(const nlohmann::json& value) {
  return value.is_structured() ? std::string("an ") + value.type_name() : value.dump();
}

InputError requestError(const std::string& request, const std::string& field, const std::string& value,
                        const std::string& problem, const std::string& allowed) {
  return InputError(SourceLocation{request, 0, 0}, field, printable(value), problem, allowed);
}

}  // namespace

// Every key must be an axis and every value a number in [-1, 1]; an axis left out is 0.
Drive driveFromJson(const std::string& body) {
  const nlohmann::json j = nlohmann::json::parse(body, nullptr, false);
  if (!j.is_object()) throw requestError("POST /api/drive", "body", body, "is not a JSON object", kDriveAllowed);
  Drive drive;
  for (const auto& [key, value] : j.items()) {
    const auto axis = std::find_if(std::begin(kDriveAxes), std::end(kDriveAxes),
                                   [&key](const auto& a) { return key == a.first; });
    if (axis == std::end(kDriveAxes))
      throw requestError("POST /api/drive", printable(key), describe(value), "is not a motion of the trainer",
                         "the keys insert, lateral, rotate, tilt and roll");
    if (!value.is_number() || !(value.get<double>() >= -1.0 && value.get<double>() <= 1.0))
      throw requestError("POST /api/drive", key, describe(value), "is not a number from -1 to 1",
                         "a number from -1 (full speed back) to 1 (full speed on), 0 to stop");
    drive.*(axis->second) = value.get<double>();
  }
  return drive;
}

void requireNoArguments(const std::string& request, const std::string& body) {
  if (body.empty()) return;
  const nlohmann::json j = nlohmann::json::parse(body, nullptr, false);
  if (!j.is_object()) throw requestError(request, "body", body, "is not a JSON object", "an empty body or {}");
  if (!j.empty())
    throw requestError(request, printable(j.items().begin().key()), describe(*j.begin()), "is not an argument of " + request,
                       "an empty body or {}: the request takes no arguments");
}

std::size_t sinceFromQuery(const std::string& text) {
  const bool digits = !text.empty() && text.size() <= 18 &&
                      std::all_of(text.begin(), text.end(), [](char c) { return c >= '0' && c <= '9'; });
  if (!digits)
    throw requestError("GET /api/frame", "since", text, "is not a sample index",
                       "a whole number from 0 (the \"next\" of the previous frame)");
  return static_cast<std::size_t>(std::stoull(text));
}

}  // namespace needlesim::live
