#pragma once
// One declaration per scenario field (FEBio's ADD_PARAMETER is the model): a table row ties a
// key to a member of a spec struct, with its unit, allowed range and meaning; the member's
// initial value in the struct is the field's default. The schema rows (`needlesim schema`,
// docs/scenario-format.md), the reading and the scenario as understood (summary.json) all come
// from the table. A default that is a formula ("grid_spacing / 2") is resolved when the file is
// read and recorded as the value it gives. Every section of a scenario is such a table
// (scenario/problem_sections.cpp, scenario/tissue_sections.cpp, engines/<engine>/<engine>_section.cpp).
#include <functional>
#include <limits>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "needlesim/scenario/schema.hpp"
#include "needlesim/scenario/yaml_section.hpp"

namespace needlesim {
struct Scenario;
}

namespace needlesim::scenario {

struct Range {
  double lo = -std::numeric_limits<double>::infinity();
  double hi = std::numeric_limits<double>::infinity();
  bool lo_open = false, hi_open = false;
};
inline Range anyValue() { return {}; }
inline Range positive() { return {0.0, std::numeric_limits<double>::infinity(), true, false}; }
inline Range nonNegative() { return {0.0, std::numeric_limits<double>::infinity(), false, false}; }
inline Range closed(double lo, double hi) { return {lo, hi, false, false}; }
inline Range openClosed(double lo, double hi) { return {lo, hi, true, false}; }  // (lo, hi]
inline Range closedOpen(double lo, double hi) { return {lo, hi, false, true}; }  // [lo, hi)

// The text of a default `si` in `unit` (e.g. "0.5 mm") when it reads back to exactly `si`,
// else in SI; "" for a plain number written as is.
std::string defaultText(double si, const units::Dim& dim, const std::string& unit);
// A FieldDoc row of a number or quantity.
FieldDoc numberDoc(const std::string& type, const std::string& key, const units::Dim& dim, Range r,
                   std::string default_text, std::string help);

template <class Spec>
class ParamTable {
 public:
  using Reader = std::function<void(Section&, Spec&, const Scenario&)>;
  explicit ParamTable(std::string type) : type_(std::move(type)) {}
  const std::string& type() const { return type_; }

  // A quantity (or with units::dim::None a plain number); its default is Spec{}.*member,
  // documented in `unit`.
  ParamTable& quantity(double Spec::*member, const std::string& key, const units::Dim& dim, const std::string& unit,
                       Range r, std::string help) {
    const double def = Spec{}.*member;
    return row(numberDoc(type_, key, dim, r, defaultText(def, dim, unit), std::move(help)),
               [member, key](Section& s, Spec& spec, const Scenario&) { spec.*member = s.number(key); });
  }
  ParamTable& number(double Spec::*member, const std::string& key, Range r, std::string help) {
    return quantity(member, key, units::dim::None, "", r, std::move(help));
  }
  // A quantity the file must give (no default).
  ParamTable& required(double Spec::*member, const std::string& key, const units::Dim& dim, Range r,
                       std::string help) {
    FieldDoc f = numberDoc(type_, key, dim, r, "", std::move(help));
    f.required = true;
    return row(std::move(f), [member, key](Section& s, Spec& spec, const Scenario&) { spec.*member = s.number(key); });
  }
  // A quantity that may be left out: the member keeps its initial value, and nothing is recorded.
  ParamTable& optional(double Spec::*member, const std::string& key, const units::Dim& dim, Range r,
                       std::string help) {
    return row(numberDoc(type_, key, dim, r, "", std::move(help)),
               [member, key](Section& s, Spec& spec, const Scenario&) {
                 if (const auto given = s.optNumber(key)) spec.*member = *given;
               });
  }
  // Free text; `shown` documents what an absent one stands for (nothing is recorded then).
  ParamTable& text(std::string Spec::*member, const std::string& key, std::string shown, std::string help) {
    return row(otherDoc(key, Kind::String, std::move(shown), std::move(help)),
               [member, key](Section& s, Spec& spec, const Scenario&) { spec.*member = s.text(key); });
  }
  // A quantity whose default is a formula of other fields (`formula` documents it); absent,
  // `resolve` gives the value, which is recorded.
  ParamTable& derived(double Spec::*member, const std::string& key, const units::Dim& dim, Range r,
                      std::string formula, std::function<double(const Spec&, const Scenario&)> resolve,
                      std::string help) {
    return row(numberDoc(type_, key, dim, r, std::move(formula), std::move(help)),
               [member, key, resolve](Section& s, Spec& spec, const Scenario& sc) {
                 const auto given = s.optNumber(key);
                 spec.*member = given ? *given : resolve(spec, sc);
                 if (!given) s.rememberNumber(key, spec.*member);
               });
  }
  // A count: a whole number in [lo, hi].
  ParamTable& count(int Spec::*member, const std::string& key, double lo, double hi, std::string help) {
    FieldDoc f = numberDoc(type_, key, units::dim::None, closed(lo, hi), std::to_string(Spec{}.*member), std::move(help));
    f.whole = true;
    return row(std::move(f), [member, key](Section& s, Spec& spec, const Scenario&) {
      spec.*member = static_cast<int>(s.number(key));  // whole (schema)
    });
  }
  // A count kept as a double (a budget such as 2e6 elements): a whole number in [lo, hi].
  ParamTable& whole(double Spec::*member, const std::string& key, double lo, double hi, std::string help) {
    FieldDoc f = numberDoc(type_, key, units::dim::None, closed(lo, hi), defaultText(Spec{}.*member, units::dim::None, ""),
                           std::move(help));
    f.whole = true;
    return row(std::move(f), [member, key](Section& s, Spec& spec, const Scenario&) { spec.*member = s.number(key); });
  }
  // A needle diameter given as a length or a gauge ("18 G"): a gauge also sets `inner` to the
  // gauge's bore, the default of the row that reads `inner` (derived, after this one).
  ParamTable& lengthOrGauge(double Spec::*outer, double Spec::*inner, const std::string& key, Range r,
                            std::string help) {
    FieldDoc f = numberDoc(type_, key, units::dim::Length, r, "", std::move(help));
    f.required = true;
    return row(std::move(f), [outer, inner, key](Section& s, Spec& spec, const Scenario&) {
      const units::Quantity q = s.lengthOrGauge(key);
      const auto gauge = q.gauge ? units::gaugeSize(static_cast<int>(q.value)) : std::nullopt;
      spec.*outer = gauge ? gauge->outer : q.value;
      if (gauge) spec.*inner = gauge->inner;
    });
  }
  // A section or list of section type `child` (`required`: the file must give it); `read`, when
  // given, reads it.
  ParamTable& section(const std::string& key, Kind kind, const std::string& child, bool required, std::string shown,
                      std::string help, Reader read = {}) {
    FieldDoc f = otherDoc(key, kind, std::move(shown), std::move(help), child);
    f.required = required;
    return row(std::move(f), std::move(read));
  }
  ParamTable& flag(bool Spec::*member, const std::string& key, std::string help) {
    return row(otherDoc(key, Kind::Bool, Spec{}.*member ? "true" : "false", std::move(help)),
               [member, key](Section& s, Spec& spec, const Scenario&) { spec.*member = s.boolean(key); });
  }
  ParamTable& word(std::string Spec::*member, const std::string& key, std::vector<std::string> choices,
                   std::string help) {
    FieldDoc f = otherDoc(key, Kind::Choice, Spec{}.*member, std::move(help));
    f.choices = std::move(choices);
    return row(std::move(f), [member, key](Section& s, Spec& spec, const Scenario&) { spec.*member = s.choice(key); });
  }
  // One of a few words, each standing for a value of the member (a bool, an int).
  template <class T>
  ParamTable& choice(T Spec::*member, const std::string& key, std::vector<std::pair<std::string, T>> words,
                     std::string help) {
    FieldDoc f = otherDoc(key, Kind::Choice, "", std::move(help));
    for (const auto& [w, v] : words) {
      f.choices.push_back(w);
      if (v == Spec{}.*member && f.default_text.empty()) f.default_text = w;
    }
    return row(std::move(f), [member, key, words](Section& s, Spec& spec, const Scenario&) {
      const std::string w = s.choice(key);
      for (const auto& [word, v] : words)
        if (word == w) spec.*member = v;
    });
  }
  // Any other row (a section, a list, a field with its own reading); `read` may be empty when
  // the section's own code reads it.
  ParamTable& row(FieldDoc f, Reader read = {}) {
    f.section = type_;
    rows_.push_back({std::move(f), std::move(read)});
    return *this;
  }
  // A step of the reading that is no field: a check across the fields read so far.
  ParamTable& check(Reader read) {
    rows_.push_back({FieldDoc{}, std::move(read)});
    return *this;
  }
  // The last `n` rows are read by another row's reader (documented here, read there).
  ParamTable& docOnly(std::size_t n = 1) {
    for (std::size_t i = 0; i < n && i < rows_.size(); ++i) rows_[rows_.size() - 1 - i].read = nullptr;
    return *this;
  }
  FieldDoc otherDoc(const std::string& key, Kind kind, std::string def, std::string help,
                    std::string child = {}) const {
    FieldDoc f;
    f.section = type_;
    f.key = key;
    f.kind = kind;
    f.default_text = std::move(def);
    f.help = std::move(help);
    f.child = std::move(child);
    return f;
  }

  std::vector<FieldDoc> docs() const {
    std::vector<FieldDoc> out;
    for (const auto& r : rows_)
      if (!r.doc.key.empty()) out.push_back(r.doc);
    return out;
  }
  // Every row with a reader, in the order declared (a derived default after what it uses).
  void read(Section& s, Spec& spec, const Scenario& sc) const {
    for (const auto& r : rows_)
      if (r.read) r.read(s, spec, sc);
  }

 private:
  struct Row {
    FieldDoc doc;
    Reader read;
  };
  std::string type_;
  std::vector<Row> rows_;
};

}  // namespace needlesim::scenario
