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

using materials::MaterialSpec;

MaterialSpec readMaterial(Section& parent, const std::string& key) {
  YAML::Node n = parent.raw(key);
  const auto& lib = materials::materialLibrary();
  auto libraryNames = [&] {
    std::string s;
    for (const auto& [name, spec] : lib) s += (s.empty() ? "" : ", ") + name;
    return s;
  };
  auto notInLibrary = [&](const std::string& name) {
    std::vector<std::string> known;
    for (const auto& [known_name, spec] : lib) known.push_back(known_name);
    const std::string near = nearestName(name, known);
    return "is not a material of the built-in library" +
           (near.empty() ? std::string() : " (did you mean '" + near + "'?)");
  };
  if (n && n.IsScalar()) {
    auto it = lib.find(n.Scalar());
    if (it == lib.end())
      throw parent.error(key, n.Scalar(), notInLibrary(n.Scalar()),
                         libraryNames() + ", or a section with 'law' and its parameters");
    parent.remember(key, n.Scalar());
    return it->second;
  }
  Section m = parent.sub(key);
  MaterialSpec spec;
  std::string base = m.text("base");
  if (!base.empty()) {
    auto it = lib.find(base);
    if (it == lib.end()) throw m.error("base", base, notInLibrary(base), libraryNames());
    spec = it->second;
  }
  std::string name = m.text("name");
  if (!name.empty()) spec.name = name;
  else m.remember("name", spec.name);
  if (m.has("law")) {
    std::string law = m.choice("law");
    if (law != spec.law) spec.params.clear();
    spec.law = law;
  } else if (base.empty()) {
    throw m.error("law", "", "is required (or give 'base')", field("material", "law").rangeText());
  }
  const auto& allowed = materials::lawParams(spec.law);
  std::string allowedText;
  for (const auto& p : allowed) allowedText += (allowedText.empty() ? "" : ", ") + p.key;
  // Every parameter key given must belong to the law.
  static const std::set<std::string> nonParams{"base", "name", "law", "density", "prony"};
  for (const auto* f : fieldsOf("material")) {
    if (nonParams.count(f->key) || !m.has(f->key)) continue;
    bool ok = false;
    for (const auto& p : allowed) ok = ok || p.key == f->key;
    if (!ok)
      throw m.error(f->key, m.raw(f->key).Scalar(), "is not a parameter of law '" + spec.law + "'", allowedText);
    spec.params[f->key] = m.number(f->key);
  }
  for (const auto& p : allowed)
    if (p.required && !spec.has(p.key))
      throw m.error(p.key, "", "is required for law '" + spec.law + "' but missing", allowedText);
  if (spec.has("K") && spec.has("nu") && spec.law != "linear")
    throw m.error("K", "", "give either K or nu for the volumetric part, not both", "K or nu");
  if (auto bad = materials::checkLawParams(spec)) throw m.error(bad->key, bad->value, bad->why, bad->allowed);
  if (auto rho = m.optNumber("density"); rho && (m.has("density") || base.empty())) spec.density = *rho;
  auto terms = m.list("prony");
  if (!terms.empty()) spec.prony.clear();
  double gsum = 0.0;
  for (std::size_t i = 0; i < terms.size(); ++i) {
    Section t = m.element(terms[i], "prony", i);
    materials::PronyTerm term{t.number("g"), t.number("tau")};
    gsum += term.g;
    spec.prony.push_back(term);
  }
  if (gsum >= 1.0)
    throw m.error("prony", fmt::format("sum g = {:g}", gsum), "the relative moduli must sum to less than 1",
                  "sum of g_i < 1 (the long-term modulus must stay positive)");
  // The small-strain moduli must be physical.
  auto mod = materials::smallStrainModuli(spec);
  if (!(mod.shear > 0.0) || !(mod.bulk > 0.0))
    throw m.errorAt(m.raw("law"), m.path(), spec.law,
                    fmt::format("gives a non-positive initial shear ({:g} Pa) or bulk ({:g} Pa) modulus", mod.shear,
                                mod.bulk),
                    "parameters with a positive initial shear modulus");
  return spec;
}

LayerSpec readLayer(Section& s, std::size_t index, bool shorthand, double blockLength, const Scenario& sc) {
  LayerSpec L;
  if (shorthand) {
    L.name = "tissue";
    L.thickness = blockLength;
    if (!s.has("material"))
      throw s.error("material", "", "is required: give tissue.material (one layer) or tissue.layers",
                    "a library name or a material section");
  } else {
    L.name = s.text("name");
    if (L.name.empty()) s.remember("name", L.name = fmt::format("layer{}", index + 1));
    if (blockLength > 0.0) {
      L.thickness = s.number("thickness");
    } else if (s.has("thickness")) {
      throw s.error("thickness", s.raw("thickness").Scalar(),
                    "has no meaning with tissue.geometry: the layers are the geometry's groups, by name",
                    "no thickness; a name that is a group of the geometry");
    }
  }
  L.material = readMaterial(s, "material");

  Section p = s.sub("puncture");
  punctureTable().read(p, L, sc);
  Section c = s.sub("cutting");
  cuttingTable().read(c, L, sc);
  Section f = s.sub("friction");
  frictionTable().read(f, L.friction, sc);
  Section in = s.sub("interaction");
  interactionTable().read(in, L, sc);
  return L;
}

void readPlacedInclusion(Section& s, InclusionSpec& I, const TissueSpec& T);

// An inclusion that is a group of tissue.geometry: its elements give its place and size.
InclusionSpec readMeshInclusion(Section& s, InclusionSpec I) {
  for (const char* k : {"shape", "depth", "lateral", "elevation", "radius"})
    if (s.has(k))
      throw s.error(k, s.raw(k).IsScalar() ? s.raw(k).Scalar() : "",
                    "has no meaning for an inclusion that is a group of tissue.geometry (its elements are the inclusion)",
                    "no shape, depth, lateral, elevation or radius; or a name that is not a group of the geometry");
  I.shape = InclusionSpec::Shape::Mesh;
  I.material = readMaterial(s, "material");
  // NaN: the layer around it, once the regions are known (tissue_geometry.cpp mapRegions)
  I.friction_coefficient = s.optNumber("friction").value_or(std::nan(""));
  I.toughness = s.optNumber("toughness").value_or(std::nan(""));
  return I;
}

InclusionSpec readInclusion(Section& s, std::size_t index, const TissueSpec& T) {
  InclusionSpec I;
  I.name = s.text("name");
  if (I.name.empty()) s.remember("name", I.name = fmt::format("inclusion{}", index + 1));
  const bool meshGroup = T.geometry && scenario::groupNames(*T.geometry).count(I.name);
  if (meshGroup) I = readMeshInclusion(s, I);
  if (!meshGroup && T.geometry && !s.has("depth") && !s.has("radius")) {
    const auto names = scenario::groupNames(*T.geometry);
    const std::vector<std::string> groups(names.begin(), names.end());
    const std::string near = nearestName(I.name, groups);
    throw s.error("name", I.name,
                  fmt::format("names no group of {}{}", T.geometry->file, near.empty() ? "" : " (did you mean '" + near + "'?)"),
                  fmt::format("the name of a group of the geometry ({}); or a sphere or cylinder placed by depth and radius",
                              groups.empty() ? "it has no named groups" : "its groups: " + fmt::format("{}", fmt::join(groups, ", "))));
  }
  if (!meshGroup) {
    for (const char* k : {"depth", "radius"})
      if (!s.has(k))
        throw s.error(k, "", "is required but missing",
                      T.geometry ? "a length; or an inclusion name that is a group of tissue.geometry" : "a length");
    readPlacedInclusion(s, I, T);
  }
  I.target = s.boolean("target");
  I.sliding = s.choice("interface") == "sliding";
  I.interface_friction = s.number("interface_friction");
  if (!I.sliding && I.interface_friction != 0.0)
    throw s.error("interface_friction", "", "applies to a sliding inclusion only", "interface: sliding");
  return I;
}

// A sphere or cylinder placed by its centre and radius.
void readPlacedInclusion(Section& s, InclusionSpec& I, const TissueSpec& T) {
  I.shape = s.choice("shape") == "cylinder" ? InclusionSpec::Shape::Cylinder : InclusionSpec::Shape::Sphere;
  I.x = s.number("depth");
  I.y = s.number("lateral");
  I.z = s.number("elevation");
  I.radius = s.number("radius");
  if (I.shape == InclusionSpec::Shape::Cylinder && I.z != 0.0)
    throw s.error("elevation", "", "has no meaning for a cylinder (its axis runs through the block's height)",
                  "elevation for a sphere only");
  const bool inside = I.x - I.radius >= 0.0 && I.x + I.radius <= T.length &&
                      std::abs(I.y) + I.radius <= 0.5 * T.width &&
                      (I.shape == InclusionSpec::Shape::Cylinder || std::abs(I.z) + I.radius <= 0.5 * T.height);
  if (!inside)
    throw s.error("radius", fmt::format("{:g} mm", I.radius * 1e3),
                  fmt::format("puts the inclusion (centre at depth {:g} mm, lateral {:g} mm, elevation {:g} mm) "
                              "outside the {:g} x {:g} x {:g} mm block",
                              I.x * 1e3, I.y * 1e3, I.z * 1e3, T.length * 1e3, T.width * 1e3, T.height * 1e3),
                  "an inclusion inside the block");
  I.material = readMaterial(s, "material");
  // Not given: the layer around it (in an imported geometry known once its regions are, mapRegions).
  const double nan = std::nan("");
  const LayerSpec* around = T.geometry ? nullptr : &T.layers[T.layerAt(I.x)];
  I.friction_coefficient = s.optNumber("friction").value_or(around ? around->friction.coefficient : nan);
  I.toughness = s.optNumber("toughness").value_or(around ? around->toughness : nan);
}

// tissue.block, or tissue.geometry (scenario/tissue_geometry.hpp) whose bounding box is the block.
void readBlockOrGeometry(Section& t, const std::string& source, TissueSpec& T, const Scenario& sc) {
  if (t.has("block") == t.has("geometry"))
    throw t.error(t.has("block") ? "geometry" : "block", "",
                  t.has("block") ? "is given together with tissue.block" : "is required but missing",
                  "either block (a generated block) or geometry (an imported one)");
  if (t.has("geometry")) {
    Section g = t.sub("geometry");
    T.geometry = scenario::placeGeometry(g, source, T);
    return;
  }
  Section b = t.sub("block");
  blockTable().read(b, T, sc);
}

// Regions, inclusion shapes and the held far side of an imported geometry.
void finishGeometry(Section& t, TissueSpec& T) {
  if (!T.geometry) return;
  auto geometry = std::make_shared<ImportedGeometry>(*T.geometry);
  scenario::mapRegions(*geometry, T, t);
  Section g = t.sub("geometry");
  scenario::markSupport(*geometry, g);
  T.geometry = geometry;
}

TissueSpec readTissue(Section& t, const std::string& source, const Scenario& sc) {
  TissueSpec T;
  readBlockOrGeometry(t, source, T, sc);
  const double blockLength = T.geometry ? 0.0 : T.length;
  auto layers = t.list("layers");
  if (layers.empty()) {
    T.layers.push_back(readLayer(t, 0, true, T.length, sc));
  } else {
    for (const char* k : {"material", "puncture", "cutting", "friction", "interaction"})
      if (t.has(k))
        throw t.error(k, "", "is given both here and in tissue.layers",
                      "either tissue.layers, or one layer's fields directly under tissue");
    for (std::size_t i = 0; i < layers.size(); ++i) {
      Section l = t.element(layers[i], "layers", i);
      T.layers.push_back(readLayer(l, i, false, blockLength, sc));
    }
  }
  if (!layers.empty() && !T.geometry) {
    double sum = 0.0;
    for (const auto& L : T.layers) sum += L.thickness;
    if (std::abs(sum - T.length) > 1e-9 + 1e-6 * T.length)
      throw t.error("layers", fmt::format("{:g} mm in all", sum * 1e3),
                    fmt::format("the layer thicknesses must add up to block.length ({:g} mm)", T.length * 1e3),
                    "thicknesses that sum to block.length");
  }
  auto inclusions = t.list("inclusions");
  for (std::size_t i = 0; i < inclusions.size(); ++i) {
    Section l = t.element(inclusions[i], "inclusions", i);
    T.inclusions.push_back(readInclusion(l, i, T));
  }
  finishGeometry(t, T);
  // The friction and toughness an inclusion takes from the layer around it, recorded as values.
  for (std::size_t i = 0; i < inclusions.size(); ++i) {
    Section l = t.element(inclusions[i], "inclusions", i);
    if (!l.has("friction")) l.rememberNumber("friction", T.inclusions[i].friction_coefficient);
    if (!l.has("toughness")) l.rememberNumber("toughness", T.inclusions[i].toughness);
  }
  return T;
}

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

Scenario readSections(Section top, const std::string& source, const Section::Record& record);

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

Scenario readRoot(const YAML::Node& root, const std::string& source, std::shared_ptr<const std::string> file) {
  auto record = std::make_shared<Section::Understood>();
  Scenario sc = readSections(Section(root, "scenario", "", file, record), source, record);
  absoluteDataPaths(record->doc, source);
  sc.understood = record->doc.dump();
  sc.given_at = std::move(record->given_at);
  return sc;
}

Scenario readSections(Section top, const std::string& source, const Section::Record& record) {
  Scenario sc;
  sc.source = source;
  sc.name = top.text("name");
  if (sc.name.empty()) {
    std::filesystem::path p(source);
    sc.name = p.has_stem() ? p.stem().string() : "scenario";
  }
  for (char ch : sc.name)
    if (!(std::isalnum(static_cast<unsigned char>(ch)) || ch == '_' || ch == '-' || ch == '.'))
      throw top.error("name", sc.name, "may be used as a folder name and must not contain spaces or symbols",
                      "letters, digits, '_', '-', '.'");
  sc.description = top.text("description");
  Section tissue = top.sub("tissue");
  sc.tissue = readTissue(tissue, source, sc);
  Section needle = top.sub("needle");
  needleTable().read(needle, sc.needle, sc);
  Section ins = top.sub("insertion");
  insertionTable().read(ins, sc.insertion, sc);
  checkEntryPoint(ins, sc.insertion, sc.tissue, sc.maxDepth());

  Section model = top.sub("model");
  modelTable().read(model, sc.model, sc);
  // Every engine's section (scenario/model_section.hpp), given or not: the record holds them all.
  // Their refusals name fields read before (Scenario::where).
  sc.given_at = record->given_at;
  for (const ModelSection* m : modelSections()) {
    Section sec = model.sub(m->key);
    m->read(sec, sc);
  }

  Section out = top.sub("output");
  outputTable().read(out, sc.output, sc);
  if (top.has("plan")) {
    Section plan = top.sub("plan");
    readPlan(plan, sc);
  }
  if (sc.totalDuration() / sc.model.time_step > 1e9)
    throw model.error("time_step", fmt::format("{:g} s", sc.model.time_step),
                      fmt::format("gives more than 1e9 steps for a {:g} s profile", sc.totalDuration()),
                      "a larger time step");
  return sc;
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
  // A results folder's summary.json: its "scenario" is the scenario as understood (docs/results.md).
  const bool record = root.IsMap() && root["scenario"] && root["scenario"].IsMap() && root["results"];
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

Scenario defaultScenario() {
  return readText(embedded::kDefaultScenario, "<built-in default: examples/gelatin_18G_3mms.yaml>");
}

}  // namespace needlesim::scenario
