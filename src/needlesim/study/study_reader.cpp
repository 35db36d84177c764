#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <set>
#include <optional>
#include <sstream>

#include "needlesim/core/error.hpp"
#include "needlesim/scenario/reader.hpp"
#include "needlesim/scenario/scenario.hpp"
#include "needlesim/scenario/yaml_document.hpp"
#include "needlesim/scenario/yaml_section.hpp"
#include "needlesim/study/field_path.hpp"
#include "needlesim/study/samplers.hpp"
#include "needlesim/study/study.hpp"

namespace needlesim::study {
namespace fs = std::filesystem;
using scenario::Section;

namespace {

const std::string kStudyFile = "a study file (see docs/studies.md)";

std::string entryProblem(const std::string& key, std::size_t index, const YAML::Node& list) {
  if (!list.IsSequence()) return fmt::format("'{}' is not a list in the base scenario, so it has no entry [{}]", key, index);
  return fmt::format("'{}' has no entry [{}] in the base scenario ({} entr{})", key, index, list.size(),
                     list.size() == 1 ? "y" : "ies");
}

std::string entryRange(const YAML::Node& list) {
  if (!list.IsSequence() || list.size() == 0) return "a list that the base scenario writes";
  return list.size() == 1 ? "index 0" : fmt::format("an index from 0 to {}", list.size() - 1);
}

// The node at `path`, creating missing mappings on the way; throws
// FieldPathError for a path the schema or the base scenario does not have.
YAML::Node nodeAt(YAML::Node root, const std::string& path) {
  YAML::Node n;
  n.reset(root);
  for (const auto& st : parseScenarioFieldPath(path)) {
    if (n.IsDefined() && !n.IsMap() && !n.IsNull())  // undefined: a section the base omits, made on assignment
      throw FieldPathError(st.key_position,
                           fmt::format("'{}' is inside a value the base scenario writes as a single value or list", st.key),
                           "a path whose sections are written as sections (key: value lines) in the base scenario");
    YAML::Node next = n[st.key];
    if (st.index) {
      if (!next.IsSequence() || *st.index >= next.size())
        throw FieldPathError(st.index_position, entryProblem(st.key, *st.index, next), entryRange(next));
      YAML::Node e = next[*st.index];
      n.reset(e);
    } else {
      n.reset(next);
    }
  }
  return n;
}

// A copy of the container `n` whose entries are the same nodes as n's, except `replacement`
// at step's key (a map) or index (a sequence): nothing reached from `n` is changed.
YAML::Node copyWith(const YAML::Node& n, const std::string& key, std::optional<std::size_t> index,
                    const YAML::Node& replacement) {
  if (index) {
    YAML::Node seq(YAML::NodeType::Sequence);
    for (std::size_t i = 0; i < n.size(); ++i) seq.push_back(i == *index ? replacement : n[i]);
    return seq;
  }
  YAML::Node map(YAML::NodeType::Map);
  bool replaced = false;
  if (n.IsMap())
    for (const auto& kv : n) {
      const bool here = kv.first.IsScalar() && kv.first.Scalar() == key;
      map.force_insert(kv.first, here ? replacement : kv.second);
      replaced = replaced || here;
    }
  if (!replaced) map.force_insert(key, replacement);
  return map;
}

// `at` with the field at steps[i..] set to `value`. The containers on the path are copied, not
// edited: an anchor's node may appear in several places (`friction: *f`), and an edit of one
// path must leave the others as they are.
YAML::Node withValueAlone(const YAML::Node& at, const std::vector<PathStep>& steps, std::size_t i,
                          const std::string& value) {
  if (i == steps.size()) return YAML::Node(value);
  const PathStep& st = steps[i];
  YAML::Node child;  // a missing section is made on the way
  if (at.IsMap() && at[st.key]) child = at[st.key];
  if (!st.index) return copyWith(at, st.key, std::nullopt, withValueAlone(child, steps, i + 1, value));
  const YAML::Node entry = child[*st.index];
  const YAML::Node list = copyWith(child, st.key, st.index, withValueAlone(entry, steps, i + 1, value));
  return copyWith(at, st.key, std::nullopt, list);
}

}  // namespace

bool isStudyFile(const fs::path& path) {
  try {
    // A scenario's own sections end the search early, and so do more keys than a study has
    // (the reader then names the first unknown one).
    const auto keys =
        scenario::topLevelKeys(scenario::readYamlFile(path, kStudyFile), {"tissue", "needle", "insertion"}, 100);
    return keys.count("vary") && keys.count("scenario") && !keys.count("tissue") && !keys.count("needle") &&
           !keys.count("insertion");
  } catch (const std::exception&) {
    return false;  // not a readable YAML document: the scenario reader reports why
  }
}

StudySpec readStudyFile(const fs::path& path) {
  if (fs::is_directory(path)) throw InputError(SourceLocation{path.string(), 0, 0}, "", "", "is a folder", kStudyFile);
  auto file = std::make_shared<const std::string>(path.string());
  YAML::Node root =
      scenario::loadYamlDocument(scenario::readYamlFile(path, kStudyFile), path.string(), kStudyFile, "study");
  if (!root || root.IsNull())
    throw InputError(SourceLocation{path.string(), 0, 0}, "", "", "is empty", "a study with scenario and vary");
  Section top(root, "study", "", file);
  StudySpec spec;
  spec.file = path;
  scenario::studyFileTable().read(top, spec, Scenario{});
  for (std::size_t i = 0; i < spec.parameters.size(); ++i) {  // the grammar of each field path
    const Parameter& par = spec.parameters[i];
    try {
      parseScenarioFieldPath(par.field);
    } catch (const FieldPathError& e) {
      throw fieldPathInputError(e, SourceLocation{path.string(), par.line, par.column}, fmt::format("vary[{}].field", i),
                                par.field);
    }
  }
  return spec;
}

void checkFieldPath(const std::string& baseYaml, const std::string& path) { nodeAt(YAML::Load(baseYaml), path); }

std::string caseYaml(const std::string& baseYaml, const Case& c) {
  YAML::Node root = YAML::Load(baseYaml);
  for (const auto& [field, value] : c.assignments) {
    nodeAt(YAML::Clone(root), field);  // refuses a path the scenario cannot hold
    root = withValueAlone(root, parseScenarioFieldPath(field), 0, value);
  }
  YAML::Emitter out;
  out << root;
  return std::string(out.c_str()) + "\n";
}

static double siValue(const std::string& text) {
  try {
    return units::parse(text).value;
  } catch (const std::invalid_argument&) {
    return NAN;
  }
}

static std::string siText(double v, const units::Dim& d) {
  if (d == units::dim::None) return fmt::format("{:.12g}", v);
  return fmt::format("{:.12g} {}", v, units::siName(d));
}

namespace {

YAML::Node loadBase(const StudySpec& spec, const std::string& baseYaml) {
  // The base file's own problems (a key given twice, a tag, not UTF-8) are named at its lines.
  return scenario::loadYamlDocument(baseYaml, spec.scenario_file.string(), "a scenario file (see docs/scenario-format.md)",
                                    "scenario");
}

// Every field path must lead to a place in the base scenario (list entries it writes).
void checkFieldsInBase(const StudySpec& spec, const YAML::Node& base) {
  for (std::size_t k = 0; k < spec.parameters.size(); ++k) {
    const Parameter& p = spec.parameters[k];
    try {
      nodeAt(YAML::Clone(base), p.field);
    } catch (const FieldPathError& e) {
      throw fieldPathInputError(e, SourceLocation{spec.file.string(), p.line, p.column}, fmt::format("vary[{}].field", k),
                                p.field);
    }
  }
}

// Where the study sets the field a case's scenario error names (the study file alone if none).
SourceLocation whereSet(const StudySpec& spec, const std::string& field) {
  for (const auto& p : spec.parameters)
    if (p.field == field) return SourceLocation{spec.file.string(), p.line, p.column};
  return SourceLocation{spec.file.string(), 0, 0};
}

void validateCase(const StudySpec& spec, const std::string& baseYaml, const Case& c) {
  std::string label = fmt::format("{} case {}", spec.file.string(), c.index);
  try {
    scenario::readText(caseYaml(baseYaml, c), label);
  } catch (const InputError& e) {
    std::string what;
    for (const auto& [f, v] : c.assignments) what += (what.empty() ? "" : ", ") + f + " = " + v;
    throw InputError(whereSet(spec, e.field()), "vary", what,
                     fmt::format("gives an invalid scenario in case {}: {}", c.index, e.what()),
                     "values the scenario accepts (see needlesim schema)");
  }
}

}  // namespace

std::vector<std::size_t> representativeCases(const StudySpec& spec, const std::vector<Case>& cases) {
  std::vector<std::size_t> order;  // by priority: the first case, extremes, then each unit or word
  std::set<std::size_t> taken;
  auto pick = [&](std::size_t i) {
    if (order.size() < kMaxCheckedCases && taken.insert(i).second) order.push_back(i);
  };
  if (cases.empty()) return order;
  pick(0);
  for (std::size_t k = 0; k < spec.parameters.size(); ++k) {
    std::size_t lo = 0, hi = 0;
    for (std::size_t i = 0; i < cases.size(); ++i) {
      double v = cases[i].values_si[k];
      if (std::isfinite(v) && !(cases[lo].values_si[k] <= v)) lo = i;
      if (std::isfinite(v) && !(cases[hi].values_si[k] >= v)) hi = i;
    }
    pick(lo);
    pick(hi);
  }
  for (std::size_t k = 0; k < spec.parameters.size(); ++k) {
    std::set<std::string> kinds;  // the unit of a number, or the text of a word (a material, a choice)
    for (std::size_t i = 0; i < cases.size(); ++i) {
      const std::string& text = cases[i].assignments[k].second;
      std::string kind = "word " + text;
      try {
        kind = "unit " + units::siName(units::parse(text).dim);
      } catch (const std::invalid_argument&) {
      }
      if (kinds.insert(kind).second) pick(i);
    }
  }
  std::sort(order.begin(), order.end());
  return order;
}

std::vector<Case> expandCases(const StudySpec& spec, const std::string& baseYaml, CaseCheck check) {
  std::vector<Case> cases;
  const auto& P = spec.parameters;
  auto push = [&](std::vector<std::pair<std::string, std::string>> a) {
    Case c;
    c.index = static_cast<int>(cases.size()) + 1;
    for (const auto& [f, v] : a) c.values_si.push_back(siValue(v));
    c.assignments = std::move(a);
    cases.push_back(std::move(c));
  };
  YAML::Node base = loadBase(spec, baseYaml);
  checkFieldsInBase(spec, base);
  auto baseValue = [&](const Parameter& p) -> units::Quantity {
    YAML::Node n;
    try {
      n = nodeAt(YAML::Clone(base), p.field);
    } catch (const std::invalid_argument& e) {
      throw InputError(SourceLocation{spec.file.string(), p.line, 0}, p.field, "", e.what(), "a field of the base scenario");
    }
    if (!n || !n.IsScalar())
      throw InputError(SourceLocation{spec.file.string(), p.line, 0}, p.field, "",
                       "one-at-a-time needs the base scenario to give this field a value", "a field written in the scenario");
    try {
      return units::parse(n.Scalar());
    } catch (const std::invalid_argument&) {
      throw InputError(SourceLocation{spec.file.string(), p.line, 0}, p.field, n.Scalar(), "is not a number in the base scenario",
                       "a numeric field");
    }
  };
  switch (spec.method) {
    case Method::Grid: {
      std::vector<int> sizes;
      for (const auto& p : P) sizes.push_back(static_cast<int>(p.values.size()));
      for (const auto& idx : gridIndices(sizes)) {
        std::vector<std::pair<std::string, std::string>> a;
        for (std::size_t k = 0; k < P.size(); ++k) a.emplace_back(P[k].field, P[k].values[idx[k]]);
        push(a);
      }
      break;
    }
    case Method::List:
      for (std::size_t i = 0; i < P.front().values.size(); ++i) {
        std::vector<std::pair<std::string, std::string>> a;
        for (const auto& p : P) a.emplace_back(p.field, p.values[i]);
        push(a);
      }
      break;
    case Method::OneAtATime: {
      std::vector<units::Quantity> b;
      for (const auto& p : P) b.push_back(baseValue(p));
      std::vector<std::pair<std::string, std::string>> a0;
      for (std::size_t k = 0; k < P.size(); ++k) a0.emplace_back(P[k].field, siText(b[k].value, b[k].dim));
      push(a0);  // case 1: the base
      for (std::size_t k = 0; k < P.size(); ++k)
        for (double pc : P[k].percent) {
          auto a = a0;
          a[k].second = siText(b[k].value * (1.0 + pc / 100.0), b[k].dim);
          push(a);
        }
      break;
    }
    case Method::LatinHypercube: {
      auto u = latinHypercube(spec.samples, static_cast<int>(P.size()), spec.seed);
      for (const auto& row : u) {
        std::vector<std::pair<std::string, std::string>> a;
        for (std::size_t k = 0; k < P.size(); ++k)
          a.emplace_back(P[k].field, siText(P[k].min + row[k] * (P[k].max - P[k].min), P[k].dim));
        push(a);
      }
      break;
    }
  }
  // Every case (or, for check, the representative ones) must be a valid scenario before anything runs.
  if (check == CaseCheck::All)
    for (const auto& c : cases) validateCase(spec, baseYaml, c);
  else
    for (std::size_t i : representativeCases(spec, cases)) validateCase(spec, baseYaml, cases[i]);
  return cases;
}

}  // namespace needlesim::study
