#include "needlesim/scenario/reader.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <numbers>

#include "needlesim/core/embedded.hpp"
#include "needlesim/core/error.hpp"
#include "needlesim/core/nearest_name.hpp"
#include "needlesim/scenario/cohesive_path_reader.hpp"
#include "needlesim/scenario/measured_data.hpp"
#include "needlesim/scenario/mesh_file.hpp"
#include "needlesim/scenario/tissue_geometry.hpp"
#include "needlesim/io/csv_reader.hpp"
#include "needlesim/scenario/yaml_document.hpp"
#include "needlesim/scenario/yaml_section.hpp"

namespace needlesim::scenario {
namespace {

const std::string kScenarioFile = "a scenario file (see docs/scenario-format.md)";

using materials::MaterialSpec;

// The markers of a real-time engine's section: inside the block (with z across the height
// when the engine is 3D), each name once.
std::vector<MarkerSpec> readMarkers(Section& engine, const Scenario& sc, bool with_z) {
  std::vector<MarkerSpec> out;
  auto list = engine.list("markers");
  const double ylo = -0.5 * sc.tissue.width - sc.insertion.entry_offset, yhi = ylo + sc.tissue.width;
  const double zmax = 0.5 * sc.tissue.height;
  for (std::size_t i = 0; i < list.size(); ++i) {
    Section m = engine.element(list[i], "markers", i);
    MarkerSpec mk{m.text("name"), m.number("x"), m.number("y"), with_z ? m.number("z") : 0.0};
    const bool inside = mk.x <= sc.tissue.length && mk.y >= ylo && mk.y <= yhi && std::abs(mk.z) <= zmax;
    if (!inside && !with_z)
      throw m.error("x", fmt::format("({:g}, {:g}) mm", mk.x * 1e3, mk.y * 1e3), "lies outside the tissue block",
                    fmt::format("0 <= x <= {:g} mm and {:g} mm <= y <= {:g} mm", sc.tissue.length * 1e3,
                                ylo * 1e3, yhi * 1e3));
    if (!inside)
      throw m.error(!(mk.x <= sc.tissue.length) ? "x" : !(mk.y >= ylo && mk.y <= yhi) ? "y" : "z", fmt::format("({:g}, {:g}, {:g}) mm", mk.x * 1e3, mk.y * 1e3, mk.z * 1e3),
                    "lies outside the tissue block",
                    fmt::format("0 <= x <= {:g} mm, {:g} mm <= y <= {:g} mm, |z| <= {:g} mm", sc.tissue.length * 1e3,
                                ylo * 1e3, yhi * 1e3, zmax * 1e3));
    for (const auto& o : out)
      if (o.name == mk.name) throw m.error("name", mk.name, "is used by two markers", "unique names");
    out.push_back(mk);
  }
  return out;
}

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

LayerSpec readLayer(Section& s, std::size_t index, bool shorthand, double blockLength) {
  LayerSpec L;
  if (shorthand) {
    L.name = "tissue";
    L.thickness = blockLength;
    if (!s.has("material"))
      throw s.error("material", "", "is required: give tissue.material (one layer) or tissue.layers",
                    "a library name or a material section");
  } else {
    L.name = s.text("name");
    if (L.name.empty()) L.name = fmt::format("layer{}", index + 1);
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
  auto pf = p.optNumber("force");
  auto pd = p.optNumber("depth");
  if (pf && pd) throw p.error("depth", "", "give the puncture force or depth, not both", "force or depth");
  if (pf) L.puncture_force = *pf;
  // A depth is converted to a force by the stiffness law at run time; keep it negative to mark it.
  if (pd) L.puncture_force = -*pd;

  Section c = s.sub("cutting");
  L.cutting_force = c.number("force");

  Section f = s.sub("friction");
  FrictionSpec& fr = L.friction;
  fr.C_p = f.number("C_p");
  fr.b_p = f.number("b_p");
  fr.C_n = f.optNumber("C_n").value_or(fr.C_p);
  fr.b_n = f.optNumber("b_n").value_or(fr.b_p);
  fr.static_band = f.number("static_band");
  // seed 003 eq 3.23: continuity of the Karnopp law at |v| = Delta v / 2 by default.
  fr.D_p = f.optNumber("D_p").value_or(fr.C_p + fr.b_p * fr.static_band / 2.0);
  fr.D_n = f.optNumber("D_n").value_or(fr.C_n + fr.b_n * fr.static_band / 2.0);
  fr.coefficient = f.number("coefficient");

  Section in = s.sub("interaction");
  L.interaction_stiffness = in.optNumber("K_T").value_or(0.0);
  L.toughness = in.optNumber("toughness").value_or(0.0);
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
  if (I.name.empty()) I.name = fmt::format("inclusion{}", index + 1);
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
  const auto& around = T.layers[T.geometry ? 0 : T.layerAt(I.x)];
  I.friction_coefficient = s.optNumber("friction").value_or(around.friction.coefficient);
  I.toughness = s.optNumber("toughness").value_or(around.toughness);
}

// tissue.block, or tissue.geometry (scenario/tissue_geometry.hpp) whose bounding box is the block.
void readBlockOrGeometry(Section& t, const std::string& source, TissueSpec& T) {
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
  T.length = b.number("length");
  T.width = b.number("width");
  T.height = b.number("height");
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

TissueSpec readTissue(Section& t, const std::string& source) {
  TissueSpec T;
  readBlockOrGeometry(t, source, T);
  const double blockLength = T.geometry ? 0.0 : T.length;
  auto layers = t.list("layers");
  if (layers.empty()) {
    T.layers.push_back(readLayer(t, 0, true, T.length));
  } else {
    for (const char* k : {"material", "puncture", "cutting", "friction", "interaction"})
      if (t.has(k))
        throw t.error(k, "", "is given both here and in tissue.layers",
                      "either tissue.layers, or one layer's fields directly under tissue");
    for (std::size_t i = 0; i < layers.size(); ++i) {
      Section l = t.element(layers[i], "layers", i);
      T.layers.push_back(readLayer(l, i, false, blockLength));
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
  return T;
}

NeedleSpec readNeedle(Section& s) {
  NeedleSpec N;
  units::Quantity od = s.lengthOrGauge("outer_diameter");
  double defaultInner = 0.0;
  if (od.gauge) {
    auto g = units::gaugeSize(static_cast<int>(od.value));
    N.outer_diameter = g->outer;
    defaultInner = g->inner;
  } else {
    N.outer_diameter = od.value;
  }
  N.inner_diameter = s.optNumber("inner_diameter").value_or(defaultInner);
  if (N.inner_diameter >= N.outer_diameter)
    throw s.error("inner_diameter", fmt::format("{:g} mm", N.inner_diameter * 1e3),
                  "must be smaller than the outer diameter",
                  fmt::format("< {:g} mm", N.outer_diameter * 1e3));
  N.length = s.number("length");
  N.bevel_angle = s.number("bevel_angle");
  std::string tip = s.choice("tip");
  N.tip = tip == "bevel" ? TipType::Bevel : tip == "conical" ? TipType::Conical : TipType::Blunt;
  N.youngs_modulus = s.number("youngs_modulus");
  N.poisson = s.number("poisson");
  N.density = s.number("density");
  return N;
}

InsertionSpec readInsertion(Section& s, const NeedleSpec& needle) {
  InsertionSpec I;
  I.entry_angle = s.number("entry_angle");
  I.entry_offset = s.number("entry_offset");
  I.start_depth = s.number("start_depth");
  I.bevel_orientation = s.number("bevel_orientation");
  if (I.start_depth > needle.length)
    throw s.error("start_depth", "", "is deeper than the needle is long", fmt::format("<= {:g} mm", needle.length * 1e3));
  auto segs = s.list("profile");
  double depth = I.start_depth;
  for (std::size_t i = 0; i < segs.size(); ++i) {
    if (!segs[i].IsMap() || segs[i].size() != 1)
      throw s.errorAt(segs[i], fmt::format("insertion.profile[{}]", i), segs[i].IsScalar() ? segs[i].Scalar() : "",
                      "each segment must be exactly one of insert / pause / retract / rotate",
                      "e.g. '- insert: {to: 60 mm, speed: 3 mm/s}'");
    Section seg = s.element(segs[i], "profile", i);
    MotionSegment m;
    std::string kind = segs[i].begin()->first.as<std::string>();
    Section body = seg.sub(kind);
    if (kind == "insert" || kind == "retract") {
      m.kind = kind == "insert" ? MotionSegment::Kind::Insert : MotionSegment::Kind::Retract;
      m.to_depth = body.number("to");
      m.speed = body.number("speed");
      if (kind == "insert") {
        m.rate = body.number("spin_rate");
        m.duty_cycle = body.number("duty_cycle");
        if (m.to_depth <= depth)
          throw body.error("to", fmt::format("{:g} mm", m.to_depth * 1e3),
                           fmt::format("an insert must go deeper than where the tip is ({:g} mm)", depth * 1e3),
                           fmt::format("> {:g} mm (use retract to go back)", depth * 1e3));
        if (m.to_depth > needle.length)
          throw body.error("to", fmt::format("{:g} mm", m.to_depth * 1e3), "is deeper than the needle is long",
                           fmt::format("<= needle.length = {:g} mm", needle.length * 1e3));
      } else if (m.to_depth >= depth) {
        throw body.error("to", fmt::format("{:g} mm", m.to_depth * 1e3),
                         fmt::format("a retract must end shallower than where the tip is ({:g} mm)", depth * 1e3),
                         fmt::format("< {:g} mm", depth * 1e3));
      }
      depth = m.to_depth;
    } else if (kind == "pause") {
      m.kind = MotionSegment::Kind::Pause;
      m.duration = body.number("duration");
    } else {
      m.kind = MotionSegment::Kind::Rotate;
      m.angle = body.number("by");
      m.rate = body.number("rate");
      m.axial = body.choice("axis") == "axial";
      if (m.angle == 0.0) throw body.error("by", "0", "a rotation must turn by a non-zero angle", "!= 0 deg");
      m.duration = std::abs(m.angle) / m.rate;
    }
    I.segments.push_back(m);
  }
  return I;
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

Scenario readSections(Section top, const std::string& source);

// Per display dimension, the unit the problem (tissue, needle, insertion) writes most often,
// the first written on a tie; the solver's settings (model, output) decide only a dimension
// the problem does not write (a time step in ms does not make durations ms).
units::DisplayUnits mostWrittenUnits(const std::vector<UnitWritten>& written) {
  units::DisplayUnits display;
  for (const auto& d : units::displayDimensions()) {
    const UnitWritten* best = nullptr;
    const auto votes = [](const UnitWritten& w) { return std::pair{w.problem, w.settings}; };
    for (const auto& w : written)
      if (units::displayDimensionOfUnit(w.unit) == &d && (!best || votes(w) > votes(*best))) best = &w;
    if (best) display.prefer(d.name, best->unit);
  }
  return display;
}

// One unit of output.units: InputError at its line for a unit of another dimension or an unknown one.
std::string displayUnitGiven(Section& us, const units::DisplayDimension& d) {
  const YAML::Node n = us.raw(std::string(d.name));
  const std::string key(d.name), text = n.IsScalar() ? n.Scalar() : std::string("a list or section");
  const std::string allowed = fmt::format("one of: {}", fmt::join(d.units, ", "));
  for (const auto u : d.units)
    if (n.IsScalar() && u == text) return us.choice(key);
  if (const units::DisplayDimension* other = units::displayDimensionOfUnit(text))
    throw us.error(key, text, fmt::format("is a unit of {}, not of {}", other->name, d.name), allowed);
  try {
    const units::Quantity q = units::parse("1 " + text);
    if (!(q.dim == d.dim))
      throw us.error(key, text, fmt::format("is a unit of {}, not of {} ({})", units::siName(q.dim), d.name, d.si),
                     allowed);
  } catch (const std::invalid_argument&) {
    throw us.error(key, text, "is not a known unit", allowed);
  }
  throw us.error(key, text, fmt::format("is not one of the units results of {} are shown in", d.name), allowed);
}

// output.units over the units written most often, else SI. Every dimension's unit is
// recorded, so that a summary.json (whose quantities are all SI) shows its results in the
// same units again.
units::DisplayUnits readDisplayUnits(Section& out) {
  Section us = out.sub("units");
  const units::DisplayUnits written = mostWrittenUnits(us.unitsWritten());
  units::DisplayUnits display;
  for (const auto& d : units::displayDimensions()) {
    const std::string key(d.name);
    if (us.has(key))
      display.set(d.name, displayUnitGiven(us, d));
    else
      display.prefer(d.name, written.unitFor(d.si));
    us.remember(key, display.unitFor(d.si));
  }
  return display;
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

Scenario readRoot(const YAML::Node& root, const std::string& source, std::shared_ptr<const std::string> file) {
  auto record = std::make_shared<Section::Understood>();
  Scenario sc = readSections(Section(root, "scenario", "", file, record), source);
  absoluteDataPaths(record->doc, source);
  sc.understood = record->doc.dump();
  sc.given_at = std::move(record->given_at);
  return sc;
}

Scenario readSections(Section top, const std::string& source) {
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
  sc.tissue = readTissue(tissue, source);
  Section needle = top.sub("needle");
  sc.needle = readNeedle(needle);
  Section ins = top.sub("insertion");
  sc.insertion = readInsertion(ins, sc.needle);
  checkEntryPoint(ins, sc.insertion, sc.tissue, sc.maxDepth());

  Section model = top.sub("model");
  sc.model.engine = model.choice("engine");
  sc.model.time_step = model.number("time_step");
  Section lumped = model.sub("lumped");
  sc.model.lumped.relaxation_time = lumped.number("relaxation_time");
  Section steer = model.sub("steering");
  {
    SteeringModelSpec& st = sc.model.steering;
    st.curvature = steer.optNumber("curvature").value_or(-1.0);  // < 0: from the tip loads
    st.beta_over_alpha = steer.number("beta_over_alpha");
    st.input_force = steer.number("input_force");
    st.tip_load = steer.choice("tip_load");
    st.energy_frame = steer.choice("energy_frame");
    st.increment = steer.number("increment");
    st.friction_dissipation = steer.number("friction_dissipation");
    st.tear_length = steer.optNumber("tear_length").value_or(0.0);  // 0: the needle radius
    st.fracture_energy = steer.number("fracture_energy");
    st.max_step = steer.number("max_step");
    st.snapshots = static_cast<int>(steer.number("snapshots"));  // a whole number (schema)
  }
  Section rt = model.sub("realtime2d");
  {
    Realtime2dModelSpec& r = sc.model.realtime2d;
    // The real-time engines' path-node coupling needs the needle within 45 deg of the entry-face normal.
    const std::string& eng = sc.model.engine;
    if ((eng == "realtime2d" || eng == "realtime3d") && sc.insertion.entry_angle < 0.25 * std::numbers::pi - 1e-12)
      throw ins.error("entry_angle", fmt::format("{:g} deg", sc.insertion.entry_angle * 180.0 / std::numbers::pi),
                      "is below the 45 deg that engine " + eng + " supports (its path-node coupling needs the needle "
                      "within 45 deg of the entry-face normal)",
                      "45 deg to 90 deg for engine " + eng);
    if (auto h = rt.optNumber("element_size")) {
      if (rt.has("nodes_depth") || rt.has("nodes_lateral"))
        throw rt.error("element_size", "", "give element_size or the node counts, not both",
                       "element_size, or nodes_depth and nodes_lateral");
      r.element_size = *h;
      r.nodes_depth = static_cast<int>(std::lround(sc.tissue.length / *h)) + 1;
      r.nodes_lateral = static_cast<int>(std::lround(sc.tissue.width / *h)) + 1;
      if (r.nodes_depth < 2 || r.nodes_lateral < 3 || r.nodes_depth * r.nodes_lateral > 4000000)
        throw rt.error("element_size", fmt::format("{:g} mm", *h * 1e3),
                       fmt::format("gives {} x {} nodes for the {:g} x {:g} mm block", r.nodes_depth,
                                   r.nodes_lateral, sc.tissue.length * 1e3, sc.tissue.width * 1e3),
                       "at least 2 x 3 and at most 4 million nodes");
    } else {
      r.nodes_depth = static_cast<int>(rt.number("nodes_depth"));  // whole numbers (schema)
      r.nodes_lateral = static_cast<int>(rt.number("nodes_lateral"));
    }
    r.refinement = rt.number("refinement");
    r.plane_strain = rt.choice("plane") == "strain";
    r.thickness = rt.number("thickness");
    r.lumped_mass = rt.choice("mass") == "lumped";
    r.rayleigh_alpha = rt.number("rayleigh_alpha");
    r.rayleigh_beta = rt.number("rayleigh_beta");
    r.newmark_gamma = rt.number("newmark_gamma");
    r.newmark_beta = rt.number("newmark_beta");
    r.spring_boundary = rt.choice("boundary") == "springs";
    if (r.spring_boundary) {
      auto k = rt.optNumber("spring_stiffness");
      if (!k) throw rt.error("spring_stiffness", "", "is required for boundary: springs", "> 0 N/m^3");
      r.spring_stiffness = *k;
    } else if (rt.has("spring_stiffness")) {
      throw rt.error("spring_stiffness", "", "only applies to boundary: springs", "boundary: springs");
    }
    r.solver = rt.choice("solver");
    r.tip_load_ratio = rt.optNumber("tip_load_ratio").value_or(-1.0);
    r.field_interval = rt.number("field_interval");
    r.relaxation = rt.choice("relaxation") == "prony";
    r.stiffening_factor = rt.number("stiffening_factor");
    r.stiffening_radius = rt.number("stiffening_radius");
    r.markers = readMarkers(rt, sc, false);
  }
  Section rt3 = model.sub("realtime3d");
  {
    Realtime3dModelSpec& r = sc.model.realtime3d;
    r.nodes_depth = static_cast<int>(rt3.number("nodes_depth"));  // whole numbers (schema)
    r.nodes_lateral = static_cast<int>(rt3.number("nodes_lateral"));
    r.nodes_height = static_cast<int>(rt3.number("nodes_height"));
    r.refinement = rt3.number("refinement");
    r.lumped_mass = rt3.choice("mass") == "lumped";
    r.rayleigh_alpha = rt3.number("rayleigh_alpha");
    r.rayleigh_beta = rt3.number("rayleigh_beta");
    r.newmark_gamma = rt3.number("newmark_gamma");
    r.newmark_beta = rt3.number("newmark_beta");
    r.hold_sides = rt3.choice("boundary") == "held";
    r.solver = rt3.choice("solver");
    r.modes = static_cast<int>(rt3.number("modes"));
    r.tip_load_ratio = rt3.optNumber("tip_load_ratio").value_or(-1.0);
    r.field_interval = rt3.number("field_interval");
    r.relaxation = rt3.choice("relaxation") == "prony";
    r.markers = readMarkers(rt3, sc, true);
  }
  Section mpmSec = model.sub("mpm");
  {
    MpmModelSpec& m = sc.model.mpm;
    m.grid_spacing = mpmSec.number("grid_spacing");
    m.particle_spacing = mpmSec.optNumber("particle_spacing").value_or(0.5 * m.grid_spacing);
    if (m.particle_spacing > m.grid_spacing)
      throw mpmSec.error("particle_spacing", fmt::format("{:g} mm", m.particle_spacing * 1e3),
                         "is larger than the grid spacing (cells without material points)",
                         fmt::format("<= grid_spacing = {:g} mm", m.grid_spacing * 1e3));
    // Checks against the block size apply only when the MPM engine will build it.
    const bool mpmRuns = sc.model.engine == "mpm";
    const double minSide = std::min({sc.tissue.length, sc.tissue.width, sc.tissue.height});
    if (mpmRuns && m.particle_spacing > 0.5 * minSide)
      throw mpmSec.error("particle_spacing", fmt::format("{:g} mm", m.particle_spacing * 1e3),
                         "leaves fewer than 2 material points across the block",
                         fmt::format("<= {:g} mm", 0.5 * minSide * 1e3));
    const double cells = (sc.tissue.length / m.grid_spacing + 7) * (sc.tissue.width / m.grid_spacing + 7) *
                         (sc.tissue.height / m.grid_spacing + 7);
    const double points = sc.tissue.length * sc.tissue.width * sc.tissue.height / std::pow(m.particle_spacing, 3);
    if (mpmRuns && (cells > 5e7 || points > 2e7))
      throw mpmSec.error("grid_spacing", fmt::format("{:g} mm", m.grid_spacing * 1e3),
                         fmt::format("gives {:.3g} grid nodes and {:.3g} material points for the block", cells, points),
                         "at most 5e7 nodes and 2e7 points (coarser spacings)");
    m.bspline = mpmSec.choice("shape") == "bspline";
    m.musl = mpmSec.choice("update") == "musl";
    m.fbar = mpmSec.choice("anti_locking") == "fbar";
    m.cfemp = mpmSec.choice("contact") == "cfemp";
    m.cfemp_element_size = mpmSec.number("cfemp_element_size");
    m.flip = mpmSec.number("flip");
    m.time_step_factor = mpmSec.number("time_step_factor");
    m.mass_scaling = mpmSec.number("mass_scaling");
    m.margin = static_cast<int>(mpmSec.number("margin"));  // whole numbers (schema)
    m.threads = static_cast<int>(mpmSec.number("threads"));
    Section faces = mpmSec.sub("faces");
    const char* names[6] = {"entry", "exit", "y_min", "y_max", "z_min", "z_max"};
    for (int f = 0; f < 6; ++f) m.faces[static_cast<std::size_t>(f)] = faces.choice(names[f]);
    m.field_interval = mpmSec.number("field_interval");
    m.marker_depth_step = mpmSec.number("marker_depth_step");
    auto markers = mpmSec.list("markers");
    for (std::size_t i = 0; i < markers.size(); ++i) {
      Section e = mpmSec.element(markers[i], "markers", i);
      MpmMarkerSpec mk{e.text("name"), e.number("x"), e.number("y"), e.number("z")};
      const double ylo = -0.5 * sc.tissue.width - sc.insertion.entry_offset, yhi = ylo + sc.tissue.width;
      if (mk.x > sc.tissue.length || !(mk.y >= ylo && mk.y <= yhi) || std::abs(mk.z) > 0.5 * sc.tissue.height)
        throw e.error("x", fmt::format("({:g}, {:g}, {:g}) mm", mk.x * 1e3, mk.y * 1e3, mk.z * 1e3),
                      "lies outside the tissue block",
                      fmt::format("0 <= x <= {:g} mm, {:g} mm <= y <= {:g} mm, |z| <= {:g} mm",
                                  sc.tissue.length * 1e3, ylo * 1e3, yhi * 1e3, 0.5 * sc.tissue.height * 1e3));
      for (const auto& o : m.markers)
        if (o.name == mk.name) throw e.error("name", mk.name, "is used by two markers", "unique names");
      m.markers.push_back(mk);
    }
    // Measured data files, resolved against the scenario file.
    auto measuredFile = [&](const char* field, const char* allowed) {
      std::string f = mpmSec.text(field);
      if (f.empty()) return f;
      std::filesystem::path p(f);
      if (p.is_relative()) {
        std::filesystem::path base = std::filesystem::path(source).parent_path();
        if (!base.empty()) p = base / p;
      }
      if (!std::filesystem::exists(p))
        throw mpmSec.error(field, f, "does not exist (paths are relative to the scenario file)", allowed);
      return p.string();
    };
    m.measured_force.path = measuredFile("measured_force", "a CSV file with columns 'depth [mm]' and 'force [N]'");
    m.measured_markers.path = measuredFile(
        "measured_markers", "a CSV file with 'depth [mm]' and per marker '<name>_ux [mm]', '<name>_uy [mm]'");
    if (!m.measured_markers.path.empty() && m.markers.empty())
      throw mpmSec.error("measured_markers", m.measured_markers.path, "has nothing to compare with",
                         "model.mpm.markers naming the measured markers");
    loadMeasuredData(m);  // InputError naming the file, line or column
  }

  Section exs = model.sub("explicit");
  {
    ExplicitModelSpec& x = sc.model.explicit_fe;
    x.dimension = exs.choice("dimension") == "3d" ? 3 : 2;
    if (exs.has("element")) x.element = exs.choice("element");
    x.element_size = exs.number("element_size");
    x.max_element_size = exs.number("max_element_size");
    x.core_width = exs.number("core_width");
    x.grading = exs.number("grading");
    x.mass_scaling = exs.number("mass_scaling");
    x.target_time_step = exs.number("target_time_step");
    x.cfl = exs.number("cfl");
    x.bulk_viscosity_linear = exs.number("bulk_viscosity_linear");
    x.bulk_viscosity_quadratic = exs.number("bulk_viscosity_quadratic");
    x.hourglass = exs.number("hourglass");
    x.damping = exs.number("damping");
    x.contact_penalty = exs.number("contact_penalty");
    x.tip_friction = exs.number("tip_friction");
    x.fixed_contact_stiffness = exs.boolean("fixed_contact_stiffness");
    x.pre_cut = exs.boolean("pre_cut");
    x.needle_model = exs.choice("needle_model");
    if (x.needle_model == "beam" && !(sc.needle.youngs_modulus > 0))
      throw exs.error("needle_model", "beam", "needs the needle's Young's modulus", "needle.youngs_modulus > 0");
    {
      Section cs = exs.sub("cohesive");
      auto& c = x.cohesive;
      c.enable = cs.boolean("enable");
      c.stiffness = cs.number("stiffness");
      c.constitutive_thickness = cs.number("constitutive_thickness");
      c.strength = cs.number("strength");
      c.critical_separation = cs.number("critical_separation");
      c.fracture_energy = cs.optNumber("fracture_energy").value_or(0.0);
      c.mode_ii_ratio = cs.number("mode_ii_ratio");
      readCohesivePath(cs, sc, source);  // crack path (cohesive_path_reader.cpp)
      c.seam = cs.choice("seam");
      c.sleeve_radius = cs.number("sleeve_radius");
      if (c.enable && c.seam == "sleeve") {
        const double ro = 0.5 * sc.needle.outer_diameter, ri = 0.5 * sc.needle.inner_diameter;
        if (x.dimension != 3 || !(ri > 0) || sc.needle.tip != TipType::Bevel)
          throw cs.error("seam", "sleeve", "needs a 3d model and a hollow bevel needle",
                         "plane, or dimension: 3d with needle.inner_diameter > 0 and tip: bevel");
        if (c.sleeve_radius != 0 && !(c.sleeve_radius > ri && c.sleeve_radius < ro))
          throw cs.error("sleeve_radius", fmt::format("{:g} mm", c.sleeve_radius * 1e3),
                         "is not between the needle's inner and outer radius",
                         fmt::format("{:g} mm < sleeve_radius < {:g} mm, or 0", ri * 1e3, ro * 1e3));
      }
      if (c.enable) {
        if (c.strength <= 0 && c.critical_separation <= 0)
          throw cs.error("strength", "0", "is not given and neither is critical_separation",
                         "strength (t_c) or critical_separation (delta_c, t_c = 2 G_c / delta_c)");
        if (c.fracture_energy <= 0)
          for (const auto& l : sc.tissue.layers)
            if (l.toughness <= 0)
              throw cs.error("fracture_energy", "0", "is not given and a layer has no interaction.toughness",
                             "fracture_energy, or interaction.toughness in every layer");
      }
    }
    x.field_interval = exs.optNumber("field_interval").value_or(0.0);
    x.threads = static_cast<int>(exs.number("threads"));
    const bool is2d = x.dimension == 2;
    if (!x.element.empty() && ((x.element == "quad4" || x.element == "tri3") != is2d))
      throw exs.error("element", x.element, "does not match the dimension", is2d ? "quad4 or tri3 for 2d" : "hex8 or tet4 for 3d");
    if (x.max_element_size < x.element_size)
      throw exs.error("max_element_size", fmt::format("{:g} mm", x.max_element_size * 1e3), "is smaller than element_size",
                      fmt::format(">= {:g} mm", x.element_size * 1e3));
  }

  Section out = top.sub("output");
  sc.output.directory = out.text("directory");
  sc.output.interval = out.number("interval");
  sc.output.checkpoint_interval = out.number("checkpoint_interval");
  sc.output.max_steps = out.number("max_steps");
  sc.output.csv = out.boolean("csv");
  sc.output.html = out.boolean("html");
  sc.output.units = readDisplayUnits(out);
  if (sc.output.interval > 0.0 && sc.output.interval < sc.model.time_step)
    throw out.error("interval", fmt::format("{:g} s", sc.output.interval), "is shorter than model.time_step",
                    fmt::format(">= {:g} s, or 0 for every step", sc.model.time_step));
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
  if (root.IsMap() && root["scenario"] && root["scenario"].IsMap() && root["results"]) root = root["scenario"];
  try {
    return readRoot(root, source_name, file);
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
