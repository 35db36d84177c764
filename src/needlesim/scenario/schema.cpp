#include "needlesim/scenario/schema.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "needlesim/core/error.hpp"
#include "needlesim/core/nearest_name.hpp"
#include "needlesim/materials/material_spec.hpp"
#include "needlesim/scenario/model_section.hpp"
#include "needlesim/scenario/problem_sections.hpp"
#include "needlesim/scenario/study_section.hpp"

namespace needlesim::scenario {
namespace {

namespace D = units::dim;

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

// The rows of a table, appended.
template <class Spec>
void addTable(std::vector<FieldDoc>& s, const ParamTable<Spec>& table) {
  for (auto& f : table.docs()) s.push_back(std::move(f));
}

// The rows of the top level, the tissue, its geometry, layers, inclusions and materials, and a
// layer's force parameters (scenario/problem_sections.hpp).
void scenarioAndTissue(std::vector<FieldDoc>& s) {
  addTable(s, scenarioTable());
  addTable(s, tissueTable());
  addTable(s, blockTable());
  addTable(s, geometryTable());
  addTable(s, surfaceTable());
  addTable(s, offsetTable());
  addTable(s, rotationTable());
  addTable(s, layerTable());
  addTable(s, inclusionTable());
  addTable(s, materialTable());
  addTable(s, pronyTable());
  addTable(s, punctureTable());
  addTable(s, cuttingTable());
  addTable(s, frictionTable());
  addTable(s, interactionTable());
}

// The rows of the needle, the insertion, the model and the engines' sections.
void needleInsertionModel(std::vector<FieldDoc>& s) {
  auto add = [&](FieldDoc f) { s.push_back(std::move(f)); };
  // --- needle and insertion (scenario/problem_sections.hpp)
  addTable(s, needleTable());
  addTable(s, insertionTable());
  addTable(s, segmentTable());
  for (const char* kind : {"insert", "retract", "pause", "rotate"}) addTable(s, segmentKindTable(kind));

  // --- model
  addTable(s, modelTable());
  // Each engine's section model.<key>, declared beside the engine (scenario/model_section.hpp).
  for (const ModelSection* m : modelSections()) {
    add(other("model", m->key, Kind::Section, "", m->help, false, m->key));
    for (auto& f : m->docs()) add(std::move(f));
  }
}

// The rows of the output, the plan and parameter studies.
void outputAndStudy(std::vector<FieldDoc>& s) {
  auto add = [&](FieldDoc f) { s.push_back(std::move(f)); };
  // --- output (scenario/problem_sections.hpp)
  addTable(s, outputTable());
  addTable(s, unitsTable());

  // --- the plan (scenario/plan_section.hpp)
  for (auto& f : planDocs()) add(std::move(f));

  // --- parameter studies (`needlesim sweep STUDY.yaml`), not part of a scenario (scenario/study_section.hpp)
  addTable(s, studyFileTable());
  addTable(s, studyParameterTable());
}

std::vector<FieldDoc> build() {
  std::vector<FieldDoc> s;
  scenarioAndTissue(s);
  needleInsertionModel(s);
  outputAndStudy(s);
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
