// The study file's fields, each declared once (study_section.hpp): the top level and an entry of
// `vary`, with the readings that are no single field (the base scenario's path, the lists, the
// bounds of a latin hypercube) and the checks across fields (a method's own fields, the number
// of cases). The field path's grammar is checked by the study reader (study/field_path.hpp).
#include "needlesim/scenario/study_section.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <stdexcept>

#include "needlesim/scenario/scenario.hpp"

namespace needlesim::scenario {
namespace {

using study::Method;
using study::Parameter;
using study::StudySpec;
namespace fs = std::filesystem;

// study.scenario: a file beside the study file (or an absolute path) that exists.
void readBaseScenario(Section& top, StudySpec& spec, const Scenario&) {
  const std::string scen = top.text("scenario");
  spec.scenario_file = fs::path(scen).is_absolute() ? fs::path(scen) : spec.file.parent_path() / scen;
  if (!fs::exists(spec.scenario_file))
    throw top.error("scenario", scen, "names a file that does not exist (" + spec.scenario_file.string() + ")",
                    "a scenario file path relative to the study file");
  if (fs::is_directory(spec.scenario_file))
    throw top.error("scenario", scen, "is a folder (" + spec.scenario_file.string() + "), give a scenario file",
                    "a scenario file path relative to the study file");
}

std::vector<std::string> scalarList(Section& s, const std::string& key) {
  std::vector<std::string> out;
  for (const auto& n : s.list(key)) {
    if (!n.IsScalar()) throw s.errorAt(n, s.fieldPath(key), "", "each entry must be a single value", "e.g. [2 mm/s, 5 mm/s]");
    out.push_back(n.Scalar());
  }
  return out;
}

void readPercent(Section& p, Parameter& par, const Scenario&) {
  for (const auto& s : scalarList(p, "percent")) {
    try {
      par.percent.push_back(std::stod(s));
    } catch (const std::exception&) {
      throw p.error("percent", s, "is not a number", "plain numbers such as -10, 10");
    }
  }
}

// The bounds of a latin hypercube: two quantities of one unit, min < max.
void readBounds(Section& p, Parameter& par) {
  const std::string &mn = par.min_text, &mx = par.max_text;
  if (mn.empty() || mx.empty()) throw p.error(mn.empty() ? "min" : "max", "", "is required for latin-hypercube", "a value with its unit");
  units::Quantity a, b;
  try {
    a = units::parse(mn);
    b = units::parse(mx);
  } catch (const std::invalid_argument& e) {
    throw p.error("min", mn + " .. " + mx, std::string("is not a valid quantity: it ") + e.what(), "a value with its unit");
  }
  if (!(a.dim == b.dim)) throw p.error("max", mx, "has another unit than min", units::siName(a.dim));
  if (!(b.value > a.value)) throw p.error("max", mx, "must be larger than min", "> " + mn);
  par.min = a.value;
  par.max = b.value;
  par.dim = a.dim;
}

// What the method needs of each entry of vary.
void requireForMethod(Section& p, Parameter& par, Method method) {
  switch (method) {
    case Method::Grid:
    case Method::List:
      if (par.values.empty()) throw p.error("values", "", "is required for method grid or list", "a list of values with units");
      break;
    case Method::OneAtATime:
      if (par.percent.empty()) throw p.error("percent", "", "is required for method one-at-a-time", "e.g. [-10, 10]");
      break;
    case Method::LatinHypercube:
      readBounds(p, par);
      break;
  }
}

void readVary(Section& top, StudySpec& spec, const Scenario& sc) {
  const auto vary = top.list("vary");
  if (vary.empty())
    throw top.error("vary", "", "is an empty list", "at least one field to vary, e.g. - {field: tissue.friction.C_p, values: [3 N/m]}");
  for (std::size_t i = 0; i < vary.size(); ++i) {
    Section p = top.element(vary[i], "vary", i);
    Parameter par;
    studyParameterTable().read(p, par, sc);
    requireForMethod(p, par, spec.method);
    spec.parameters.push_back(std::move(par));
  }
}

// Cases the method makes, counted without making them (saturates above kMaxCases).
std::uint64_t caseCount(const StudySpec& spec) {
  const auto& P = spec.parameters;
  switch (spec.method) {
    case Method::Grid: {
      std::uint64_t n = 1;
      for (const auto& p : P) n = std::min<std::uint64_t>(n * p.values.size(), study::kMaxCases + 1);
      return P.empty() ? 0 : n;
    }
    case Method::List:
      return P.empty() ? 0 : P.front().values.size();
    case Method::OneAtATime: {
      std::uint64_t n = 1;
      for (const auto& p : P) n += p.percent.size();
      return n;
    }
    case Method::LatinHypercube:
      return static_cast<std::uint64_t>(spec.samples);
  }
  return 0;
}

// Across the fields: the lists of method list, the number of cases.
void checkCases(Section& top, StudySpec& spec, const Scenario&) {
  const YAML::Node vary = top.raw("vary");
  if (spec.method == Method::List)
    for (const auto& par : spec.parameters)
      if (par.values.size() != spec.parameters.front().values.size())
        throw top.errorAt(vary[0], "vary", par.field, "method list needs the same number of values for every field",
                          fmt::format("{} values each", spec.parameters.front().values.size()));
  const std::uint64_t n = caseCount(spec);
  if (n <= study::kMaxCases) return;
  if (spec.method == Method::LatinHypercube)
    throw top.error("samples", std::to_string(spec.samples), "gives more cases than a study may have",
                    fmt::format("at most {} cases", study::kMaxCases));
  const std::string count = spec.method == Method::Grid
                                ? fmt::format("more than {} cases (the product of the numbers of values)", study::kMaxCases)
                                : fmt::format("{} cases", n);
  throw top.errorAt(vary[0], "vary", "", "gives " + count,
                    fmt::format("at most {} cases; split the study or use method latin-hypercube", study::kMaxCases));
}

ParamTable<StudySpec> makeStudy() {
  using S = StudySpec;
  ParamTable<S> t("study");
  FieldDoc scenarioDoc = t.otherDoc("scenario", Kind::String, "", "base scenario file, relative to the study file");
  scenarioDoc.required = true;
  t.row(std::move(scenarioDoc), readBaseScenario)
      .text(&S::name, "name", "study file name", "name of the study, used for its folder")
      .check([](Section&, S& spec, const Scenario&) {
        if (spec.name.empty()) spec.name = spec.file.stem().string();
      })
      .choice(&S::method, "method",
              {{"grid", Method::Grid}, {"list", Method::List}, {"one-at-a-time", Method::OneAtATime},
               {"latin-hypercube", Method::LatinHypercube}},
              "grid: every combination; list: the i-th values together; one-at-a-time: the base case and each "
              "parameter changed by each percent; latin-hypercube: samples between min and max")
      .section("vary", Kind::List, "parameter", true, "", "the fields to vary", readVary)
      .count(&S::samples, "samples", 1.0, static_cast<double>(study::kMaxCases), "number of latin-hypercube samples");
  FieldDoc seed = numberDoc("study", "seed", units::dim::None, closed(0.0, 1e18), std::to_string(S{}.seed),
                            "random seed of the latin hypercube");
  seed.whole = true;
  t.row(std::move(seed),
        [](Section& s, S& spec, const Scenario&) { spec.seed = static_cast<std::uint64_t>(s.number("seed")); })
      .count(&S::parallel, "parallel", 0.0, 1024.0, "cases run at once per process (0 = all cores)")
      .text(&S::directory, "directory", "results/<name>", "study folder: one folder per case, study.csv, report.html")
      .check(checkCases);
  return t;
}

ParamTable<Parameter> makeParameter() {
  using P = Parameter;
  ParamTable<P> t("parameter");
  FieldDoc field = t.otherDoc("field", Kind::String, "",
                              "scenario field to vary, e.g. tissue.friction.C_p or insertion.profile[0].insert.speed");
  field.required = true;
  t.row(std::move(field),
        [](Section& p, P& par, const Scenario&) {
          par.field = p.text("field");
          const SourceLocation at = p.location(p.raw("field"));
          par.line = at.line;
          par.column = at.column;
        })
      .row(t.otherDoc("values", Kind::List, "", "grid / list: the values, with units (e.g. [2 mm/s, 5 mm/s])"),
           [](Section& p, P& par, const Scenario&) { par.values = scalarList(p, "values"); })
      .row(t.otherDoc("percent", Kind::List, "", "one-at-a-time: changes of the base value in percent (e.g. [-10, 10])"),
           readPercent)
      .text(&P::min_text, "min", "", "latin-hypercube: lower bound, with unit")
      .text(&P::max_text, "max", "", "latin-hypercube: upper bound, with unit");
  return t;
}

}  // namespace

const ParamTable<StudySpec>& studyFileTable() {
  static const auto t = makeStudy();
  return t;
}

const ParamTable<Parameter>& studyParameterTable() {
  static const auto t = makeParameter();
  return t;
}

}  // namespace needlesim::scenario
