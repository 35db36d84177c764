// The JSON documents of the trainer's API (web_server.hpp).
#include <cmath>

#include "needlesim/core/error.hpp"
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
          {"tip", {s.tip_x, s.tip_y, 0.0}}, {"phase", s.phase}};
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
          {"puncture", f.punctureDepth < 0.0 ? nlohmann::json(nullptr) : nlohmann::json(f.punctureDepth)},
          {"field", {{"displacement", floats(f.field.displacement)}, {"scalar", floats(f.field.scalar)},
                     {"name", f.field.scalarName}, {"unit", f.field.scalarUnit},
                     {"step", f.fieldStep}, {"cost", f.fieldCost}}},
          {"needle", floats(f.needle)},
          {"samples", std::move(samples)},
          {"next", total}};
}

Drive driveFromJson(const std::string& body) {
  const nlohmann::json j = nlohmann::json::parse(body, nullptr, false);
  if (!j.is_object())
    throw InputError(SourceLocation{"POST /api/drive", 0, 0}, "body", printable(body), "is not a JSON object",
                     "{\"insert\": -1..1, \"lateral\": ..., \"rotate\": ..., \"tilt\": ..., \"roll\": ...}");
  const auto get = [&](const char* key) { return j.contains(key) && j[key].is_number() ? j[key].get<double>() : 0.0; };
  return Drive{get("insert"), get("lateral"), get("rotate"), get("tilt"), get("roll")};
}

}  // namespace needlesim::live
