#include "needlesim/scenario/schema.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "needlesim/core/error.hpp"
#include "needlesim/core/nearest_name.hpp"
#include "needlesim/materials/material_spec.hpp"
#include "needlesim/scenario/model_section.hpp"
#include "needlesim/scenario/problem_sections.hpp"

namespace needlesim::scenario {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
namespace D = units::dim;

FieldDoc q(std::string sec, std::string key, units::Dim d, std::string def, double lo, double hi,
           bool lo_open, bool hi_open, std::string help, bool required = false) {
  FieldDoc f;
  f.section = std::move(sec);
  f.key = std::move(key);
  f.kind = d == D::None ? Kind::Number : Kind::Quantity;
  f.dim = d;
  f.default_text = std::move(def);
  f.required = required;
  f.lo = lo;
  f.hi = hi;
  f.lo_open = lo_open;
  f.hi_open = hi_open;
  f.help = std::move(help);
  return f;
}
FieldDoc positive(std::string sec, std::string key, units::Dim d, std::string def, std::string help,
                  bool required = false) {
  return q(std::move(sec), std::move(key), d, std::move(def), 0.0, kInf, true, false,
           std::move(help), required);
}
FieldDoc nonneg(std::string sec, std::string key, units::Dim d, std::string def, std::string help) {
  return q(std::move(sec), std::move(key), d, std::move(def), 0.0, kInf, false, false,
           std::move(help));
}
// A count: a whole number in [lo, hi].
FieldDoc count(std::string sec, std::string key, std::string def, double lo, double hi, std::string help) {
  FieldDoc f = q(std::move(sec), std::move(key), D::None, std::move(def), lo, hi, false, false, std::move(help));
  f.whole = true;
  return f;
}
FieldDoc other(std::string sec, std::string key, Kind k, std::string def, std::string help,
               bool required = false, std::string child = {}, std::vector<std::string> choices = {}) {
  FieldDoc f;
  f.section = std::move(sec);
  f.key = std::move(key);
  f.kind = k;
  f.default_text = std::move(def);
  f.help = std::move(help);
  f.required = required;
  f.child = std::move(child);
  f.choices = std::move(choices);
  return f;
}

// The rows of the top level, the tissue, its geometry and layers.
void scenarioAndTissue(std::vector<FieldDoc>& s) {
  auto add = [&](FieldDoc f) { s.push_back(std::move(f)); };
  // --- top level
  add(other("scenario", "name", Kind::String, "file name", "name of the scenario, used for the results folder"));
  add(other("scenario", "description", Kind::String, "", "free text"));
  add(other("scenario", "tissue", Kind::Section, "", "the tissue block and its layers", true, "tissue"));
  add(other("scenario", "needle", Kind::Section, "", "needle geometry and material", true, "needle"));
  add(other("scenario", "insertion", Kind::Section, "", "entry pose and motion profile", true, "insertion"));
  add(other("scenario", "model", Kind::Section, "engine: lumped", "which engine and its parameters", false, "model"));
  add(other("scenario", "output", Kind::Section, "", "where and what to write", false, "output"));
  add(other("scenario", "plan", Kind::Section, "", "a needle path to plan (needlesim plan, docs/planning.md)", false, "plan"));

  // --- tissue
  add(other("tissue", "block", Kind::Section, "", "block size (required unless tissue.geometry is given)", false, "block"));
  add(other("tissue", "geometry", Kind::Section, "",
            "an imported tissue geometry instead of the block: a Gmsh mesh or script, or closed surfaces meshed by "
            "Gmsh; its groups are the layers and inclusions, by name (engines explicit, mpm, realtime2d)",
            false, "geometry"));
  add(other("tissue", "layers", Kind::List, "",
            "layers from the entry face inwards; omit for one layer and write the layer's fields "
            "(material, puncture, cutting, friction, interaction) directly under tissue",
            false, "layer"));
  add(other("tissue", "inclusions", Kind::List, "",
            "bodies embedded in the block (a tumour to target, a vessel): engines mpm, explicit and realtime2d",
            false, "inclusion"));
  for (const auto& f : blockTable().docs()) add(f);

  // --- geometry (scenario/tissue_geometry.hpp)
  add(other("geometry", "file", Kind::String, "",
            "a Gmsh mesh (.msh, format 2 or 4, ASCII or binary) or script (.geo), or one closed surface (.stl, .ply, "
            ".vtk, .off, .obj); relative to the scenario file"));
  add(other("geometry", "surfaces", Kind::List, "", "several closed surfaces (instead of file), one body each",
            false, "surface"));
  add(other("geometry", "unit", Kind::Choice, "", "length unit of the file's coordinates", true, {},
            {"m", "cm", "mm", "um"}));
  add(other("geometry", "translate", Kind::Section, "0 mm", "placement: shift after the rotation", false, "offset"));
  add(other("geometry", "rotate", Kind::Section, "0 deg",
            "placement: rotations about the tissue frame's x, then y, then z axis, before the shift", false,
            "rotation"));
  add(positive("geometry", "element_size", D::Length, "1/20 of the bounding box diagonal",
               "size of the elements Gmsh makes from surfaces or a .geo script"));
  add(positive("geometry", "support_depth", D::Length, "20 % of the body's depth",
               "the boundary facing away from the needle within this depth of the deepest point is held fixed"));
  add(count("geometry", "max_elements", "2e6", 1.0, 1e9,
             "refuse a geometry that holds or would make more elements (estimated before meshing from the volume "
             "and the largest element size); raise it to allow a finer mesh"));
  add(positive("geometry", "max_mesh_time", D::Time, "120 s",
               "reading and meshing the geometry is stopped and refused after this long (wall clock and CPU time)"));
  add(q("geometry", "max_mesh_memory_mib", D::None, "4096", 64.0, 1e7, false, false,
        "memory (MiB) reading and meshing the geometry may take; more is refused"));
  add(other("surface", "file", Kind::String, "", "a closed surface (.stl, .ply, .vtk, .off, .obj); relative to the scenario file", true));
  add(other("surface", "body", Kind::String, "the file's stem", "name of the body it bounds: a layer or inclusion name"));
  for (const char* axis : {"x", "y", "z"}) {
    add(q("offset", axis, D::Length, "0 mm", -kInf, kInf, false, false, std::string("shift along ") + axis));
    add(q("rotation", axis, D::Angle, "0 deg", -2 * M_PI, 2 * M_PI, false, false,
          std::string("rotation about the tissue frame's ") + axis + " axis (right hand)"));
  }

  // --- layer
  add(other("layer", "name", Kind::String, "layer<i>", "label in results"));
  add(positive("layer", "thickness", D::Length, "",
               "thickness along the surface normal; layers must add up to block.length (required with a block; "
               "none with tissue.geometry, whose groups are the layers)"));
  add(other("layer", "material", Kind::MaterialRef, "", "a library name (e.g. gelatin_10wt) or a material section", true, "material"));
  add(other("layer", "puncture", Kind::Section, "", "puncture threshold; omitted = punctures on contact", false, "puncture"));
  add(other("layer", "cutting", Kind::Section, "force: 0 N", "cutting at the tip", false, "cutting"));
  add(other("layer", "friction", Kind::Section, "all zero", "friction along the shaft", false, "friction"));
  add(other("layer", "interaction", Kind::Section, "", "needle-tissue interaction parameters", false, "interaction"));
}

// The rows of inclusions, materials and a layer's force parameters.
void inclusionsAndMaterials(std::vector<FieldDoc>& s) {
  auto add = [&](FieldDoc f) { s.push_back(std::move(f)); };
  // --- inclusion (tissue frame, docs/models/frame.md)
  add(other("inclusion", "name", Kind::String, "inclusion<i>", "label in results"));
  add(other("inclusion", "shape", Kind::Choice, "sphere",
            "sphere, or cylinder (a vessel: axis out of the insertion plane, through the block's height)", false, {},
            {"sphere", "cylinder"}));
  add(q("inclusion", "depth", D::Length, "", 0.0, kInf, false, false,
        "centre: depth x from the entry face (required unless the inclusion is a group of tissue.geometry)"));
  add(q("inclusion", "lateral", D::Length, "0 mm", -kInf, kInf, false, false,
        "centre: y across the width from the block's centre line (+ = the side a tilted needle goes to)"));
  add(q("inclusion", "elevation", D::Length, "0 mm", -kInf, kInf, false, false,
        "centre: z across the height from the block's mid-plane (sphere only)"));
  add(positive("inclusion", "radius", D::Length, "", "radius (required unless the inclusion is a group of tissue.geometry)"));
  add(other("inclusion", "material", Kind::MaterialRef, "", "a library name or a material section", true, "material"));
  add(nonneg("inclusion", "friction", D::None, "the surrounding layer's",
             "Coulomb coefficient of needle contact inside it; not given: friction.coefficient of the layer around it "
             "(the layer at its centre; a group of tissue.geometry: the layer its elements touch most)"));
  add(nonneg("inclusion", "toughness", D::ForcePerLength, "the surrounding layer's",
             "rupture toughness G_c inside it; not given: interaction.toughness of the layer around it (as friction)"));
  add(other("inclusion", "interface", Kind::Choice, "bonded",
            "bonded (shares the tissue's material points or nodes) or sliding (a separate body in frictional "
            "contact with the tissue: mpm only)", false, {}, {"bonded", "sliding"}));
  add(nonneg("inclusion", "interface_friction", D::None, "0", "Coulomb coefficient between a sliding inclusion and the tissue"));
  add(other("inclusion", "target", Kind::Bool, "false", "the needle aims at it: its displacement is the targeting error"));

  // --- material
  add(other("material", "base", Kind::String, "", "start from a library material and override the fields given"));
  add(other("material", "name", Kind::String, "custom", "label"));
  add(other("material", "law", Kind::Choice, "", "constitutive law (required unless base is given)", false, {},
            materials::lawNames()));
  add(positive("material", "density", D::Density, "1000 kg/m^3", "mass density"));
  for (const auto& p : materials::lawParameterFields())  // each law's parameters (materials/laws/)
    add(q("material", p.key, p.pressure ? D::Pressure : D::None, "", p.lo, p.hi, p.loOpen, p.hiOpen, p.help));
  add(other("material", "prony", Kind::List, "", "Prony series terms (seed 001 eqs 1-4)", false, "prony"));
  add(q("prony", "g", D::None, "", 0.0, 1.0, true, true, "relative modulus g_i; the g_i must sum to less than 1", true));
  add(positive("prony", "tau", D::Time, "", "relaxation time tau_i", true));

  // --- a layer's force parameters (scenario/problem_sections.hpp)
  for (const auto& docs : {punctureTable().docs(), cuttingTable().docs(), frictionTable().docs(),
                           interactionTable().docs()})
    for (const auto& f : docs) add(f);
}

// The rows of the needle, the insertion, the model and the engines' sections.
void needleInsertionModel(std::vector<FieldDoc>& s) {
  auto add = [&](FieldDoc f) { s.push_back(std::move(f)); };
  // --- needle and insertion (scenario/problem_sections.hpp)
  for (const auto& f : needleTable().docs()) add(f);
  for (const auto& f : insertionTable().docs()) add(f);
  for (const auto& f : segmentTable().docs()) add(f);
  for (const char* kind : {"insert", "retract", "pause", "rotate"})
    for (const auto& f : segmentKindTable(kind).docs()) add(f);

  // --- model
  for (const auto& f : modelTable().docs()) add(f);
  // Each engine's section model.<key>, declared beside the engine (scenario/model_section.hpp).
  for (const ModelSection* m : modelSections()) {
    add(other("model", m->key, Kind::Section, "", m->help, false, m->key));
    for (auto& f : m->docs()) add(std::move(f));
  }
}

// The rows of the output and parameter studies.
void outputAndStudy(std::vector<FieldDoc>& s) {
  auto add = [&](FieldDoc f) { s.push_back(std::move(f)); };
  // --- output (scenario/problem_sections.hpp)
  for (const auto& f : outputTable().docs()) add(f);
  for (const auto& d : units::displayDimensions()) {
    std::vector<std::string> allowed(d.units.begin(), d.units.end());
    std::string words(d.name);
    std::replace(words.begin(), words.end(), '_', ' ');
    add(other("units", std::string(d.name), Kind::Choice, "",
              fmt::format("unit of {} results (SI: {}) on the terminal and in report.html", words, d.si), false, {},
              allowed));
  }

  // --- the plan (scenario/plan_section.hpp)
  for (auto& f : planDocs()) add(std::move(f));

  // --- parameter studies (`needlesim sweep STUDY.yaml`), not part of a scenario
  add(other("study", "scenario", Kind::String, "", "base scenario file, relative to the study file", true));
  add(other("study", "name", Kind::String, "study file name", "name of the study, used for its folder"));
  add(other("study", "method", Kind::Choice, "grid",
            "grid: every combination; list: the i-th values together; one-at-a-time: the base case and each "
            "parameter changed by each percent; latin-hypercube: samples between min and max",
            false, {}, {"grid", "list", "one-at-a-time", "latin-hypercube"}));
  add(other("study", "vary", Kind::List, "", "the fields to vary", true, "parameter"));
  // The upper bound of samples is study::kMaxCases.
  add(count("study", "samples", "10", 1.0, 1e5, "number of latin-hypercube samples"));
  add(count("study", "seed", "1", 0.0, 1e18, "random seed of the latin hypercube"));
  add(count("study", "parallel", "0", 0.0, 1024.0, "cases run at once per process (0 = all cores)"));
  add(other("study", "directory", Kind::String, "results/<name>", "study folder: one folder per case, study.csv, report.html"));
  add(other("parameter", "field", Kind::String, "", "scenario field to vary, e.g. tissue.friction.C_p or insertion.profile[0].insert.speed", true));
  add(other("parameter", "values", Kind::List, "", "grid / list: the values, with units (e.g. [2 mm/s, 5 mm/s])"));
  add(other("parameter", "percent", Kind::List, "", "one-at-a-time: changes of the base value in percent (e.g. [-10, 10])"));
  add(other("parameter", "min", Kind::String, "", "latin-hypercube: lower bound, with unit"));
  add(other("parameter", "max", Kind::String, "", "latin-hypercube: upper bound, with unit"));
}

std::vector<FieldDoc> build() {
  std::vector<FieldDoc> s;
  scenarioAndTissue(s);
  inclusionsAndMaterials(s);
  needleInsertionModel(s);
  outputAndStudy(s);
  // A one-layer tissue may carry the layer's fields directly.
  for (const char* k : {"material", "puncture", "cutting", "friction", "interaction"}) {
    for (const auto& f : std::vector<FieldDoc>(s)) {
      if (f.section == "layer" && f.key == k) {
        FieldDoc g = f;
        g.section = "tissue";
        g.required = false;
        g.help += " (one-layer shorthand)";
        s.push_back(g);
      }
    }
  }
  return s;
}

std::string num(double v) { return fmt::format("{:g}", v); }

}  // namespace

std::string FieldDoc::rangeText() const {
  if (kind == Kind::Choice) {
    std::string t = "one of: ";
    for (std::size_t i = 0; i < choices.size(); ++i) t += (i ? ", " : "") + choices[i];
    return t;
  }
  if (kind != Kind::Quantity && kind != Kind::Number) return "";
  // fmt rather than "literal" + std::string temporaries (GCC 12 warns falsely on those).
  const std::string unit = kind == Kind::Quantity ? fmt::format(" {}", units::siName(dim)) : std::string();
  bool hasLo = std::isfinite(lo), hasHi = std::isfinite(hi);
  if (!hasLo && !hasHi) return "any";
  if (hasLo && !hasHi) return fmt::format("{} {}{}", lo_open ? ">" : ">=", num(lo), unit);
  if (!hasLo && hasHi) return fmt::format("{} {}{}", hi_open ? "<" : "<=", num(hi), unit);
  return fmt::format("{}{}{}, {}{}{}", whole ? "a whole number in " : "", lo_open ? "(" : "[", num(lo), num(hi),
                     hi_open ? ")" : "]", unit);
}

bool FieldDoc::inRange(double v) const {
  if (lo_open ? !(v > lo) : !(v >= lo)) return false;
  if (hi_open ? !(v < hi) : !(v <= hi)) return false;
  return true;
}

const std::vector<FieldDoc>& schema() {
  static const std::vector<FieldDoc> s = build();
  return s;
}

const FieldDoc& field(const std::string& section, const std::string& key) {
  for (const auto& f : schema())
    if (f.section == section && f.key == key) return f;
  throw Error("internal: field " + section + "." + key + " is not in the schema");
}

const FieldDoc* findField(const std::string& section, const std::string& key) {
  for (const auto& f : schema())
    if (f.section == section && f.key == key) return &f;
  return nullptr;
}

// A study file (docs/studies.md) read as a scenario: its top-level 'scenario:' or 'vary:'.
static bool studyKeyAtTop(const std::string& field_path, const std::string& key, const std::string& section) {
  return section == "scenario" && field_path == key && (key == "scenario" || key == "vary");
}

InputError unknownFieldError(SourceLocation where, const std::string& field_path, const std::string& key,
                             const std::string& section) {
  if (studyKeyAtTop(field_path, key, section))
    return InputError(std::move(where), field_path, key,
                      "makes this file a study (a base scenario and the fields to vary), not a scenario",
                      "a study runs with `needlesim sweep FILE` (`needlesim check` checks either kind)");
  std::string allowed;
  std::vector<std::string> known;
  for (const auto* f : fieldsOf(section)) {
    allowed += (allowed.empty() ? "" : ", ") + f->key;
    known.push_back(f->key);
  }
  const std::string near = nearestName(key, known);
  return InputError(std::move(where), field_path, key,
                    "is not a known field of section '" + section + "'" +
                        (near.empty() ? std::string() : " (did you mean '" + near + "'?)"),
                    allowed);
}

std::vector<const FieldDoc*> fieldsOf(const std::string& section) {
  std::vector<const FieldDoc*> out;
  for (const auto& f : schema())
    if (f.section == section) out.push_back(&f);
  return out;
}

std::vector<std::string> sectionTypes() {
  std::vector<std::string> out;
  for (const auto& f : schema())
    if (std::find(out.begin(), out.end(), f.section) == out.end()) out.push_back(f.section);
  return out;
}

static std::string unitText(const FieldDoc& f) {
  switch (f.kind) {
    case Kind::Quantity: return units::examples(f.dim);
    case Kind::Number: return "number";
    case Kind::String: return "text";
    case Kind::Choice: return "word";
    case Kind::Bool: return "true/false";
    case Kind::Section: return "section `" + f.child + "`";
    case Kind::List: return "list of `" + f.child + "`";
    case Kind::MaterialRef: return "name or section `material`";
  }
  return "";
}

std::string schemaMarkdown() {
  std::string out;
  for (const auto& sec : sectionTypes()) {
    out += fmt::format("\n### `{}`\n\n| field | unit | required | default | allowed | meaning |\n|---|---|---|---|---|---|\n", sec);
    for (const auto* f : fieldsOf(sec))
      out += fmt::format("| `{}` | {} | {} | {} | {} | {} |\n", f->key, unitText(*f),
                         f->required ? "yes" : "no", f->default_text, f->rangeText(), f->help);
  }
  return out;
}

std::string schemaText() {
  std::string out;
  for (const auto& sec : sectionTypes()) {
    out += "[" + sec + "]\n";
    for (const auto* f : fieldsOf(sec)) {
      out += fmt::format("  {:<18} {:<30} {}{}{}\n", f->key, unitText(*f),
                         f->required ? "required" : ("default " + (f->default_text.empty() ? std::string("none") : f->default_text)),
                         f->rangeText().empty() ? "" : "; " + f->rangeText(), "");
      out += fmt::format("  {:<18} {}\n", "", f->help);
    }
  }
  return out;
}

}  // namespace needlesim::scenario
