#include "needlesim/scenario/yaml_section.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace needlesim::scenario {

Section::Section(YAML::Node node, std::string type, std::string path,
                 std::shared_ptr<const std::string> file, Record record)
    : node_(std::move(node)),
      type_(std::move(type)),
      path_(std::move(path)),
      file_(std::move(file)),
      record_(std::move(record)) {
  if (!node_.IsMap()) {
    std::string what = node_.IsScalar() ? node_.Scalar() : (node_.IsSequence() ? "a list" : "nothing");
    throw errorAt(node_, path_.empty() ? "(top level)" : path_, what, "must be a section of 'key: value' lines",
                  "the fields of section '" + type_ + "' (see needlesim schema)");
  }
  checkKeys();
}

SourceLocation Section::location(const YAML::Node& at) const {
  SourceLocation loc;
  loc.file = file_ ? *file_ : std::string();
  auto mark = at.Mark();
  if (!mark.is_null()) {
    loc.line = mark.line + 1;
    loc.column = mark.column + 1;
  }
  return loc;
}

std::string Section::fieldPath(const std::string& key) const {
  return path_.empty() ? key : path_ + "." + key;
}

namespace {
// "tissue.layers[0].material" + "E" -> /tissue/layers/0/material/E
nlohmann::json::json_pointer pointerOf(const std::string& path, const std::string& key) {
  std::string p;
  for (char c : path) {
    if (c == '.' || c == '[') p += '/';
    else if (c != ']') p += c;
  }
  return nlohmann::json::json_pointer((path.empty() ? "" : "/" + p) + "/" + key);
}
}  // namespace

void Section::remember(const std::string& key, nlohmann::json value) const {
  if (!record_) return;
  record_->doc[pointerOf(path_, key)] = std::move(value);
  const YAML::Node& node = node_;  // const: reading never adds the key
  const YAML::Node given = node[key];
  if (given && !given.Mark().is_null()) record_->given_at[fieldPath(key)] = location(given);
}

void Section::rememberNumber(const std::string& key, const FieldDoc& f, double value) const {
  if (!record_) return;
  if (f.kind == Kind::Quantity)
    remember(key, fmt::format("{} {}", value, units::siName(f.dim)));  // shortest text that reads back exactly
  else
    remember(key, value);
}

void Section::rememberNumber(const std::string& key, double value) const {
  rememberNumber(key, field(type_, key), value);
}

std::vector<UnitWritten> Section::unitsWritten() const {
  return record_ ? record_->units_written : std::vector<UnitWritten>{};
}

std::map<std::string, SourceLocation> Section::givenAt() const {
  return record_ ? record_->given_at : std::map<std::string, SourceLocation>{};
}

void Section::countUnit(const units::Quantity& written) const {
  if (!record_ || written.gauge || !units::displayDimensionOfUnit(written.unit)) return;
  const bool settings = path_.starts_with("model") || path_.starts_with("output");
  auto& list = record_->units_written;
  auto it = std::find_if(list.begin(), list.end(), [&](const UnitWritten& w) { return w.unit == written.unit; });
  if (it == list.end()) it = list.insert(list.end(), UnitWritten{written.unit});
  ++(settings ? it->settings : it->problem);
}

InputError Section::errorAt(const YAML::Node& at, const std::string& field, const std::string& value,
                            const std::string& problem, const std::string& allowed) const {
  return InputError(location(at), field, value, problem, allowed);
}

InputError Section::error(const std::string& key, const std::string& value, const std::string& problem,
                          const std::string& allowed) const {
  YAML::Node n = node_[key];
  return errorAt(n ? n : node_, fieldPath(key), value, problem, allowed);
}

bool Section::has(const std::string& key) const {
  return static_cast<bool>(node_[key]) && !node_[key].IsNull();
}

YAML::Node Section::raw(const std::string& key) const {
  used_.insert(key);
  return node_[key];
}

static std::string scalarOf(const YAML::Node& n) {
  if (n.IsScalar()) return n.Scalar();
  if (n.IsSequence()) return "a list";
  if (n.IsMap()) return "a section";
  return "";
}

units::Quantity Section::parseQuantity(const std::string& key, const FieldDoc& f, const YAML::Node& n,
                                       const std::string& text) {
  units::Quantity qv;
  try {
    qv = units::parse(text);
  } catch (const std::invalid_argument& e) {
    throw errorAt(n, fieldPath(key), text, std::string("is not a valid quantity: it ") + e.what(),
                  f.kind == Kind::Quantity ? "a number with a unit of " + units::siName(f.dim) + " (" +
                                                 units::examples(f.dim) + ")"
                                           : "a plain number");
  }
  return qv;
}

// Why a quantity field refuses a dimensionless value: no unit at all, or a fraction ("55 %").
static std::string noUnitProblem(const units::Quantity& qv) {
  if (qv.unit.empty()) return "has no unit";
  return "has the unit '" + qv.unit + "', which is a fraction (a plain number), not a unit of this field";
}

double Section::number(const std::string& key) {
  auto v = optNumber(key);
  if (!v) {
    const FieldDoc& f = field(type_, key);
    throw errorAt(node_, fieldPath(key), "", "is required but missing",
                  f.kind == Kind::Quantity ? "a quantity in " + units::examples(f.dim) : "a number");
  }
  return *v;
}

std::optional<double> Section::optNumber(const std::string& key) {
  const FieldDoc& f = field(type_, key);
  used_.insert(key);
  YAML::Node n = node_[key];
  std::string text;
  YAML::Node at = n;
  if (!n || n.IsNull()) {
    if (f.required)
      throw errorAt(node_, fieldPath(key), "", "is required but missing",
                    f.kind == Kind::Quantity ? "a quantity in " + units::examples(f.dim) : "a number");
    // Defaults that are plain values ("20 deg") apply here; symbolic ones ("C_p") are resolved by the reader.
    if (f.default_text.empty()) return std::nullopt;
    try {
      units::Quantity d = units::parse(f.default_text);
      rememberNumber(key, f, d.value);
      return d.value;
    } catch (const std::invalid_argument&) {
      return std::nullopt;
    }
  }
  if (!n.IsScalar())
    throw errorAt(n, fieldPath(key), scalarOf(n), "must be a single value",
                  f.kind == Kind::Quantity ? "a quantity in " + units::examples(f.dim) : "a number");
  text = n.Scalar();
  units::Quantity qv = parseQuantity(key, f, n, text);
  if (qv.gauge)
    throw errorAt(n, fieldPath(key), text, "a gauge is allowed only for needle.outer_diameter",
                  units::examples(f.dim));
  if (f.kind == Kind::Quantity) {
    if (qv.dim == units::dim::None)
      throw errorAt(n, fieldPath(key), text, noUnitProblem(qv),
                    "a number with a unit of " + units::siName(f.dim) + ", e.g. " + units::examples(f.dim));
    if (!(qv.dim == f.dim))
      throw errorAt(n, fieldPath(key), text,
                    "has the wrong unit (" + units::siName(qv.dim) + " is not " + units::siName(f.dim) + ")",
                    units::examples(f.dim));
  } else if (!(qv.dim == units::dim::None)) {
    throw errorAt(n, fieldPath(key), text, "must be a plain number without a unit", "a plain number");
  }
  if (!std::isfinite(qv.value))
    throw errorAt(n, fieldPath(key), text, "is not a finite number", f.rangeText());
  if (!f.inRange(qv.value))
    throw errorAt(n, fieldPath(key), text,
                  f.kind == Kind::Quantity
                      ? fmt::format("is out of range ({:g} {} in SI)", qv.value, units::siName(f.dim))
                      : fmt::format("is out of range ({:g})", qv.value),
                  f.rangeText());
  if (f.whole && qv.value != std::floor(qv.value))
    throw errorAt(n, fieldPath(key), text, "must be a whole number (it counts something)", f.rangeText());
  rememberNumber(key, f, qv.value);
  countUnit(qv);
  return qv.value;
}

units::Quantity Section::lengthOrGauge(const std::string& key) {
  const FieldDoc& f = field(type_, key);
  used_.insert(key);
  YAML::Node n = node_[key];
  if (!n || n.IsNull())
    throw errorAt(node_, fieldPath(key), "", "is required but missing", "a length (mm) or a gauge (e.g. 18 G)");
  if (!n.IsScalar()) throw errorAt(n, fieldPath(key), scalarOf(n), "must be a single value", "a length or a gauge");
  units::Quantity qv = parseQuantity(key, f, n, n.Scalar());
  if (qv.gauge) {
    if (qv.value != std::floor(qv.value) || !units::gaugeSize(static_cast<int>(qv.value)))
      throw errorAt(n, fieldPath(key), n.Scalar(), "is not a known needle gauge", "10 G to 34 G");
    remember(key, n.Scalar());
    return qv;
  }
  if (qv.dim == units::dim::None)
    throw errorAt(n, fieldPath(key), n.Scalar(), noUnitProblem(qv), "a length such as 1.27 mm, or a gauge such as 18 G");
  if (!(qv.dim == units::dim::Length))
    throw errorAt(n, fieldPath(key), n.Scalar(), "has the wrong unit", "a length (m, mm) or a gauge (G)");
  if (!f.inRange(qv.value)) throw errorAt(n, fieldPath(key), n.Scalar(), "is out of range", f.rangeText());
  rememberNumber(key, f, qv.value);
  countUnit(qv);
  return qv;
}

std::string Section::text(const std::string& key) {
  const FieldDoc& f = field(type_, key);
  used_.insert(key);
  YAML::Node n = node_[key];
  if (!n || n.IsNull()) {
    if (f.required) throw errorAt(node_, fieldPath(key), "", "is required but missing", "text");
    return {};
  }
  if (!n.IsScalar()) throw errorAt(n, fieldPath(key), scalarOf(n), "must be text", "text");
  remember(key, n.Scalar());
  return n.Scalar();
}

std::string Section::choice(const std::string& key) {
  const FieldDoc& f = field(type_, key);
  used_.insert(key);
  YAML::Node n = node_[key];
  if (!n || n.IsNull()) {
    if (f.required) throw errorAt(node_, fieldPath(key), "", "is required but missing", f.rangeText());
    remember(key, f.default_text);
    return f.default_text;
  }
  if (!n.IsScalar()) throw errorAt(n, fieldPath(key), scalarOf(n), "must be one word", f.rangeText());
  for (const auto& c : f.choices)
    if (c == n.Scalar()) {
      remember(key, c);
      return c;
    }
  throw errorAt(n, fieldPath(key), n.Scalar(), "is not a known choice", f.rangeText());
}

bool Section::boolean(const std::string& key) {
  const FieldDoc& f = field(type_, key);
  used_.insert(key);
  YAML::Node n = node_[key];
  if (!n || n.IsNull()) {
    remember(key, f.default_text == "true");
    return f.default_text == "true";
  }
  if (n.IsScalar()) {
    const std::string& s = n.Scalar();
    const bool yes = s == "true" || s == "yes" || s == "on", no = s == "false" || s == "no" || s == "off";
    if (yes || no) {
      remember(key, yes);
      return yes;
    }
  }
  throw errorAt(n, fieldPath(key), scalarOf(n), "is not a boolean", "true or false");
}

Section Section::sub(const std::string& key) {
  const FieldDoc& f = field(type_, key);
  used_.insert(key);
  YAML::Node n = node_[key];
  if (!n || n.IsNull()) {
    if (f.required) throw errorAt(node_, fieldPath(key), "", "is required but missing", "a section '" + f.child + "'");
    return Section(YAML::Node(YAML::NodeType::Map), f.child, fieldPath(key), file_, record_);
  }
  if (!n.IsMap())
    throw errorAt(n, fieldPath(key), scalarOf(n), "must be a section of 'key: value' lines",
                  "the fields of '" + f.child + "' (see needlesim schema)");
  return Section(n, f.child, fieldPath(key), file_, record_);
}

std::vector<YAML::Node> Section::list(const std::string& key) {
  const FieldDoc& f = field(type_, key);
  used_.insert(key);
  YAML::Node n = node_[key];
  std::vector<YAML::Node> out;
  if (!n || n.IsNull()) {
    if (f.required) throw errorAt(node_, fieldPath(key), "", "is required but missing", "a list of '" + f.child + "'");
    return out;
  }
  if (!n.IsSequence())
    throw errorAt(n, fieldPath(key), scalarOf(n), "must be a list ('- ...' lines)", "a list of '" + f.child + "'");
  for (const auto& e : n) out.push_back(e);
  if (out.empty() && f.required) throw errorAt(n, fieldPath(key), "[]", "must not be empty", "at least one entry");
  return out;
}

Section Section::element(const YAML::Node& node, const std::string& key, std::size_t index) {
  const FieldDoc& f = field(type_, key);
  return Section(node, f.child, fmt::format("{}[{}]", fieldPath(key), index), file_, record_);
}

void Section::checkKeys() const {
  for (auto it = node_.begin(); it != node_.end(); ++it) {
    std::string k = it->first.as<std::string>();
    if (!findField(type_, k)) throw unknownFieldError(location(it->first), fieldPath(k), k, type_);
  }
}

}  // namespace needlesim::scenario
