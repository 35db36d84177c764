#include "needlesim/scenario/schema.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "needlesim/core/error.hpp"
#include "needlesim/core/nearest_name.hpp"
#include "needlesim/materials/material_spec.hpp"
#include "needlesim/scenario/model_section.hpp"

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
// Plausibility bounds on sizes: a length above them is a slip of the unit ("55 Mm"), not tissue.
// Tissue samples, phantoms and organs of needle-insertion studies are centimetres to tens of
// centimetres (a human torso is under 0.5 m across), so a block side is at most 1 m. The longest
// clinical needles (spinal, biopsy, brachytherapy) are about 0.3 m long, so a needle is at most
// 1 m long; the thickest gauge of the table is 10 G (3.4 mm) and trocars reach about 10 mm, so an
// outer diameter is at most 20 mm.
constexpr double kMaxBlockSide = 1.0;
constexpr double kMaxNeedleLength = 1.0;
constexpr double kMaxNeedleDiameter = 0.02;
FieldDoc extent(std::string sec, std::string key, double hi, std::string help, bool required = true) {
  return q(std::move(sec), std::move(key), D::Length, "", 0.0, hi, true, false, std::move(help), required);
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

// model.engine: one of the registered engines (engines/registry.cpp).
FieldDoc engineChoice() {
  std::string help = "engine:";
  std::vector<std::string> names;
  for (const auto& [name, summary] : engineNames()) {
    help += fmt::format("{} {}: {}", names.empty() ? "" : ";", name, summary);
    names.push_back(name);
  }
  return other("model", "engine", Kind::Choice, "lumped", help, false, {}, names);
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
  add(extent("block", "length", kMaxBlockSide, "extent along the insertion axis (entry face to exit face)"));
  add(extent("block", "width", kMaxBlockSide, "extent across the insertion axis, in the insertion plane"));
  add(extent("block", "height", kMaxBlockSide, "extent out of the insertion plane"));

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

  // --- lumped force parameters of a layer
  add(positive("puncture", "force", D::Force, "", "force at which the tip punctures the layer (give force or depth)"));
  add(positive("puncture", "depth", D::Length, "", "indentation at which the tip punctures the layer (give force or depth)"));
  add(nonneg("cutting", "force", D::Force, "0 N", "constant cutting force while the tip advances inside the layer (seed 003 eq 3.24)"));
  add(nonneg("friction", "C_p", D::ForcePerLength, "0 N/m", "dynamic friction per length in contact, insertion (seed 003 eqs 3.23, 5.1)"));
  add(nonneg("friction", "b_p", D::ForceTimePerArea, "0 N s/m^2", "viscous friction per length in contact, insertion"));
  add(nonneg("friction", "C_n", D::ForcePerLength, "C_p", "dynamic friction per length, retraction"));
  add(nonneg("friction", "b_n", D::ForceTimePerArea, "b_p", "viscous friction per length, retraction"));
  add(nonneg("friction", "D_p", D::ForcePerLength, "C_p + b_p static_band/2", "static friction limit per length, positive direction"));
  add(nonneg("friction", "D_n", D::ForcePerLength, "C_n + b_n static_band/2", "static friction limit per length, negative direction (magnitude)"));
  add(positive("friction", "static_band", D::Velocity, "0.1 mm/s", "Karnopp band Delta v: |v| < Delta v/2 sticks"));
  add(nonneg("friction", "coefficient", D::None, "0", "Coulomb coefficient for the contact engines (seed 001: 0.3)"));
  add(positive("interaction", "K_T", D::Pressure, "", "needle-tissue interaction stiffness per unit length (seed 002 eq 13)"));
  add(positive("interaction", "toughness", D::ForcePerLength, "", "rupture toughness G_c (seed 002 eq 19, seed 004 Table I)"));
}

// The rows of the needle, the insertion, the model and the engines' sections.
void needleInsertionModel(std::vector<FieldDoc>& s) {
  auto add = [&](FieldDoc f) { s.push_back(std::move(f)); };
  const double deg = M_PI / 180.0;
  // --- needle
  add(extent("needle", "outer_diameter", kMaxNeedleDiameter, "outer diameter, or a gauge such as 18 G"));
  add(nonneg("needle", "inner_diameter", D::Length, "from the gauge, else 0 mm", "bore diameter (0 = solid)"));
  add(extent("needle", "length", kMaxNeedleLength, "free length from the base to the tip"));
  add(q("needle", "bevel_angle", D::Angle, "20 deg", 0.0, 90.0 * deg, true, false, "tip angle alpha of the bevel or cone"));
  add(other("needle", "tip", Kind::Choice, "bevel", "tip type", false, {}, {"bevel", "conical", "blunt"}));
  add(positive("needle", "youngs_modulus", D::Pressure, "200 GPa", "needle material (stainless steel; Nitinol is 50 GPa in seed 002)"));
  add(q("needle", "poisson", D::None, "0.3", -1.0, 0.5, true, true, "needle Poisson ratio"));
  add(positive("needle", "density", D::Density, "7850 kg/m^3", "needle density"));

  // --- insertion
  add(q("insertion", "entry_angle", D::Angle, "90 deg", 0.0, 90.0 * deg, true, false, "angle between needle and entry face (90 deg = perpendicular)"));
  add(q("insertion", "entry_offset", D::Length, "0 mm", -kInf, kInf, false, false,
        "entry point from the centre of the entry face, in the insertion plane; inside the face (|offset| < block.width / 2)"));
  add(q("insertion", "start_depth", D::Length, "0 mm", -kInf, kInf, false, false, "tip position along the needle axis at t = 0 (negative = outside)"));
  add(q("insertion", "bevel_orientation", D::Angle, "0 deg", -kInf, kInf, false, false, "initial axial orientation of the bevel"));
  add(other("insertion", "profile", Kind::List, "", "motion segments, each one of insert / pause / retract / rotate", true, "segment"));
  add(other("segment", "insert", Kind::Section, "", "advance the tip", false, "insert"));
  add(other("segment", "pause", Kind::Section, "", "hold still", false, "pause"));
  add(other("segment", "retract", Kind::Section, "", "withdraw the tip", false, "retract"));
  add(other("segment", "rotate", Kind::Section, "", "rotate the needle at the current depth", false, "rotate"));
  add(q("insert", "to", D::Length, "", -kInf, kInf, false, false, "tip depth at the end of the segment (deeper than at its start)", true));
  add(positive("insert", "speed", D::Velocity, "", "insertion speed", true));
  add(nonneg("insert", "spin_rate", D::AngularVelocity, "0 deg/s", "axial spin rate while inserting (duty-cycled steering)"));
  add(q("insert", "duty_cycle", D::None, "0", 0.0, 1.0, false, false, "fraction of each cycle spent spinning"));
  add(q("retract", "to", D::Length, "", -kInf, kInf, false, false, "tip depth at the end of the segment (shallower than at its start)", true));
  add(positive("retract", "speed", D::Velocity, "", "retraction speed", true));
  add(positive("pause", "duration", D::Time, "", "how long to hold still", true));
  add(q("rotate", "by", D::Angle, "", -kInf, kInf, false, false, "rotation angle (non-zero)", true));
  add(positive("rotate", "rate", D::AngularVelocity, "", "rotation rate", true));
  add(other("rotate", "axis", Kind::Choice, "axial", "about the needle axis (bevel flip) or the base in the insertion plane",
            false, {}, {"axial", "in-plane"}));

  // --- model
  add(engineChoice());
  add(positive("model", "time_step", D::Time, "1 ms", "integration step"));
  // Each engine's section model.<key>, declared beside the engine (scenario/model_section.hpp).
  for (const ModelSection* m : modelSections()) {
    add(other("model", m->key, Kind::Section, "", m->help, false, m->key));
    for (auto& f : m->docs()) add(std::move(f));
  }
}

// The rows of the output and parameter studies.
void outputAndStudy(std::vector<FieldDoc>& s) {
  auto add = [&](FieldDoc f) { s.push_back(std::move(f)); };
  // --- output
  add(other("output", "directory", Kind::String, "results/<name>", "results folder; an existing one is never overwritten"));
  add(nonneg("output", "interval", D::Time, "0 s", "sampling interval of the time series (0 = every step)"));
  add(nonneg("output", "checkpoint_interval", D::Time, "10 min",
             "wall-clock time between checkpoints of a long run, written beside the results folder for `needlesim run "
             "--resume` (0 = none; mpm only so far)"));
  add(q("output", "max_steps", D::None, "1e6", 1.0, 1e15, false, false, "refuse a run whose step estimate (printed before the first step, and by `needlesim check`) is larger; raise it to allow a long run"));
  add(other("output", "csv", Kind::Bool, "true", "write CSV time series"));
  add(other("output", "html", Kind::Bool, "true", "write report.html"));
  add(other("output", "units", Kind::Section, "",
            "units the terminal and report.html show results in, per dimension (files keep SI); a dimension not "
            "given here is shown in the unit the file writes most often for it (tissue, needle and insertion "
            "first, then model and output), else in SI, or in the unit that shows the value (an axis or column: "
            "its largest) between 0.1 and 1000 when that one does not (20 s, not 20000 ms)",
            false, "units"));
  for (const auto& d : units::displayDimensions()) {
    std::vector<std::string> allowed(d.units.begin(), d.units.end());
    std::string words(d.name);
    std::replace(words.begin(), words.end(), '_', ' ');
    add(other("units", std::string(d.name), Kind::Choice, "",
              fmt::format("unit of {} results (SI: {}) on the terminal and in report.html", words, d.si), false, {},
              allowed));
  }

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
