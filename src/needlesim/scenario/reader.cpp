#include "needlesim/scenario/reader.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "needlesim/core/embedded.hpp"
#include "needlesim/core/error.hpp"
#include "needlesim/core/nearest_name.hpp"
#include "needlesim/scenario/mesh_file.hpp"
#include "needlesim/scenario/model_section.hpp"
#include "needlesim/scenario/problem_sections.hpp"
#include "needlesim/scenario/tissue_geometry.hpp"
#include "needlesim/io/csv_reader.hpp"
#include "needlesim/scenario/yaml_document.hpp"
#include "needlesim/scenario/yaml_section.hpp"

namespace needlesim::scenario {
namespace {

const std::string kScenarioFile = "a scenario file (see docs/scenario-format.md)";

// The entry point must lie on the entry face, which spans the block's width in the insertion plane.
// An imported geometry: the path must cross it (scenario/tissue_geometry.hpp findEntry).
void checkEntryPoint(Section& ins, const InsertionSpec& I, TissueSpec& T, double maxDepth) {
  if (T.geometry) {
    auto geometry = std::make_shared<ImportedGeometry>(*T.geometry);
    scenario::findEntry(*geometry, I, maxDepth, ins);
    T.geometry = geometry;
    return;
  }
  const double half = 0.5 * T.width;
  if (std::abs(I.entry_offset) < half) return;
  const std::string written = ins.has("entry_offset") ? ins.raw("entry_offset").Scalar() : std::string();
  const auto inUserUnit = [&](double si) { return units::inUnitOf(si, units::dim::Length, written); };
  throw ins.error("entry_offset", written,
                  fmt::format("puts the entry point outside the entry face, which spans {} to {} about its centre "
                              "(block.width = {})",
                              inUserUnit(-half), inUserUnit(half), inUserUnit(T.width)),
                  fmt::format("{} < entry_offset < {}", inUserUnit(-half), inUserUnit(half)));
}

// Data files named in a scenario, relative to the scenario file: the record keeps them
// absolute so that a scenario re-read from its summary.json finds the same files.
void absoluteDataPaths(nlohmann::json& record, const std::string& source) {
  if (source.empty() || source[0] == '<') return;
  const std::filesystem::path base = std::filesystem::absolute(std::filesystem::path(source)).parent_path();
  for (const char* at : {"/model/mpm/measured_force", "/model/mpm/measured_markers", "/tissue/geometry/file",
                         "/model/explicit/cohesive/path_file"}) {
    const nlohmann::json::json_pointer ptr(at);
    if (!record.contains(ptr) || !record[ptr].is_string()) continue;
    const std::filesystem::path p(record[ptr].get<std::string>());
    if (!p.empty() && p.is_relative()) record[ptr] = (base / p).lexically_normal().string();
  }
  const nlohmann::json::json_pointer surfaces("/tissue/geometry/surfaces");
  if (record.contains(surfaces) && record[surfaces].is_array())
    for (auto& s : record[surfaces])
      if (s.contains("file") && s["file"].is_string() && std::filesystem::path(s["file"].get<std::string>()).is_relative())
        s["file"] = (base / s["file"].get<std::string>()).lexically_normal().string();
}

// scenario.name: given, or the file's stem; it names the results folder.
void readName(Section& top, Scenario& sc, const Scenario&) {
  sc.name = top.text("name");
  if (sc.name.empty()) {
    std::filesystem::path p(sc.source);
    sc.name = p.has_stem() ? p.stem().string() : "scenario";
  }
  for (char ch : sc.name)
    if (!(std::isalnum(static_cast<unsigned char>(ch)) || ch == '_' || ch == '-' || ch == '.'))
      throw top.error("name", sc.name, "may be used as a folder name and must not contain spaces or symbols",
                      "letters, digits, '_', '-', '.'");
}

// The model: engine and time step, then every engine's section (scenario/model_section.hpp),
// given or not: the record holds them all. Their refusals name fields read before (Scenario::where).
void readModel(Section& top, Scenario& sc, const Scenario&) {
  Section model = top.sub("model");
  modelTable().read(model, sc.model, sc);
  sc.given_at = model.givenAt();
  for (const ModelSection* m : modelSections()) {
    Section sec = model.sub(m->key);
    m->read(sec, sc);
  }
}

void readOutput(Section& top, Scenario& sc, const Scenario&) {
  Section out = top.sub("output");
  outputTable().read(out, sc.output, sc);
  if (sc.totalDuration() / sc.model.time_step > 1e9)
    throw top.sub("model").error("time_step", fmt::format("{:g} s", sc.model.time_step),
                                 fmt::format("gives more than 1e9 steps for a {:g} s profile", sc.totalDuration()),
                                 "a larger time step");
}

ParamTable<Scenario> makeScenario() {
  using S = Scenario;
  ParamTable<S> t("scenario");
  t.row(t.otherDoc("name", Kind::String, "file name", "name of the scenario, used for the results folder"), readName)
      .text(&S::description, "description", "", "free text")
      .section("tissue", Kind::Section, "tissue", true, "", "the tissue block and its layers",
               [](Section& top, S& sc, const S&) {
                 Section tissue = top.sub("tissue");
                 tissueTable().read(tissue, sc.tissue, sc);
               })
      .section("needle", Kind::Section, "needle", true, "", "needle geometry and material",
               [](Section& top, S& sc, const S&) {
                 Section needle = top.sub("needle");
                 needleTable().read(needle, sc.needle, sc);
               })
      .section("insertion", Kind::Section, "insertion", true, "", "entry pose and motion profile",
               [](Section& top, S& sc, const S&) {
                 Section ins = top.sub("insertion");
                 insertionTable().read(ins, sc.insertion, sc);
                 checkEntryPoint(ins, sc.insertion, sc.tissue, sc.maxDepth());
               })
      .section("model", Kind::Section, "model", false, "engine: lumped", "which engine and its parameters", readModel)
      .section("output", Kind::Section, "output", false, "", "where and what to write", readOutput)
      .section("plan", Kind::Section, "plan", false, "", "a needle path to plan (needlesim plan, docs/planning.md)",
               [](Section& top, S& sc, const S&) {
                 if (!top.has("plan")) return;
                 Section plan = top.sub("plan");
                 readPlan(plan, sc);
               });
  return t;
}

Scenario readRoot(const YAML::Node& root, const std::string& source, std::shared_ptr<const std::string> file) {
  auto record = std::make_shared<Section::Understood>();
  Scenario sc;
  sc.source = source;
  Section top(root, "scenario", "", file, record);
  scenarioTable().read(top, sc, sc);
  absoluteDataPaths(record->doc, source);
  sc.understood = record->doc.dump();
  sc.given_at = std::move(record->given_at);
  return sc;
}

}  // namespace

const ParamTable<Scenario>& scenarioTable() {
  static const auto t = makeScenario();
  return t;
}

namespace {
// A results folder's summary.json holds the scenario as understood under "scenario" (docs/results.md).
bool isResultsRecord(const YAML::Node& root) {
  return root.IsMap() && root["scenario"] && root["scenario"].IsMap() && root["results"];
}
}  // namespace

Scenario readText(std::string_view yaml, const std::string& source_name) {
  auto file = std::make_shared<const std::string>(source_name);
  // A summary.json (JSON, a '{' first) holds the scenario under "scenario": its keys are checked
  // when the scenario is read, not while parsing.
  const auto first = yaml.find_first_not_of(" \t\r\n");
  const bool json = first != std::string_view::npos && yaml[first] == '{';
  YAML::Node root = loadYamlDocument(yaml, source_name, kScenarioFile, json ? "" : "scenario");
  if (!root || root.IsNull())
    throw InputError(SourceLocation{source_name, 0, 0}, "", "", "is empty",
                     "a scenario with tissue, needle and insertion sections");
  const bool record = isResultsRecord(root);
  if (record) root = root["scenario"];
  try {
    Scenario sc = readRoot(root, source_name, file);
    sc.from_record = record;
    return sc;
  } catch (const YAML::Exception& e) {
    SourceLocation loc{source_name, e.mark.is_null() ? 0 : e.mark.line + 1,
                       e.mark.is_null() ? 0 : e.mark.column + 1};
    throw InputError(loc, "", "", "could not be read: " + e.msg, "see docs/scenario-format.md");
  }
}

Scenario readFile(const std::filesystem::path& path) {
  return readText(readYamlFile(path, kScenarioFile), path.string());
}

std::string engineNamedIn(const std::filesystem::path& path) {
  try {
    YAML::Node root = loadYamlDocument(readYamlFile(path, kScenarioFile), path.string(), kScenarioFile);
    if (isResultsRecord(root)) root = root["scenario"];
    if (!root.IsMap() || !root["model"] || !root["model"].IsMap() || !root["model"]["engine"]) return ModelSpec{}.engine;
    const YAML::Node engine = root["model"]["engine"];
    return engine.IsScalar() ? engine.Scalar() : std::string();
  } catch (const std::exception&) {
    return {};
  }
}

Scenario defaultScenario() {
  return readText(embedded::kDefaultScenario, "<built-in default: examples/gelatin_18G_3mms.yaml>");
}

}  // namespace needlesim::scenario
