#include "needlesim/study/field_path.hpp"

#include <fmt/format.h>

#include <cctype>
#include <charconv>

#include "needlesim/core/nearest_name.hpp"
#include "needlesim/scenario/schema.hpp"

namespace needlesim::study {

FieldPathError::FieldPathError(std::size_t position, std::string problem, std::string allowed)
    : std::invalid_argument(fmt::format("at character {}: {}; allowed: {}", position, problem, allowed)),
      position_(position),
      problem_(std::move(problem)),
      allowed_(std::move(allowed)) {}

namespace {

constexpr const char* kGrammar = "dot-separated names with [index] for a list entry, e.g. insertion.profile[0].insert.speed";

bool isKeyStart(char c) { return std::isalpha(static_cast<unsigned char>(c)) || c == '_'; }
bool isKeyChar(char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; }
bool isDigit(char c) { return c >= '0' && c <= '9'; }

// Reads the path left to right; `pos` is 0-based, errors report it 1-based.
class PathScanner {
 public:
  explicit PathScanner(const std::string& path) : p_(path) {}

  std::vector<PathStep> steps() {
    if (p_.empty()) throw FieldPathError(1, "the path is empty", kGrammar);
    std::vector<PathStep> out;
    while (true) {
      out.push_back(step());
      if (pos_ == p_.size()) return out;
      const char* allowed = "letters, digits and '_' in a name; '.' between names; [index] after a list's name";
      if (p_[pos_] == '.') {
        ++pos_;
        continue;
      }
      if (out.back().index) fail("follows ']' where '.' or the end of the path must come", allowed);
      failAtCharacter("is not allowed in a field name", allowed);
    }
  }

 private:
  [[noreturn]] void fail(const std::string& problem, const std::string& allowed) const {
    throw FieldPathError(pos_ + 1, badPart() + " " + problem, allowed);
  }
  [[noreturn]] void failAtCharacter(const std::string& problem, const std::string& allowed) const {
    throw FieldPathError(pos_ + 1, "'" + printable(p_.substr(pos_, 1)) + "' " + problem, allowed);
  }

  // The text from the bad character up to the next separator, quoted (or "the end").
  std::string badPart() const {
    if (pos_ == p_.size()) return "the end";
    std::size_t end = pos_ + 1;
    while (end < p_.size() && end - pos_ < 20 && std::string(".[]").find(p_[end]) == std::string::npos)
      ++end;
    return "'" + printable(p_.substr(pos_, end - pos_)) + "'";
  }

  PathStep step() {
    PathStep st;
    st.key_position = pos_ + 1;
    if (pos_ == p_.size() || !isKeyStart(p_[pos_]))
      fail(pos_ > 0 && p_[pos_ - 1] == '.' ? "follows '.' where a field name must start"
                                            : "is where a field name must start",
           "a name starting with a letter or '_' (" + std::string(kGrammar) + ")");
    while (pos_ < p_.size() && isKeyChar(p_[pos_])) st.key += p_[pos_++];
    if (pos_ < p_.size() && p_[pos_] == '[') {
      ++pos_;
      st.index_position = pos_ + 1;
      st.index = index();
    }
    return st;
  }

  std::size_t index() {
    std::size_t begin = pos_;
    while (pos_ < p_.size() && isDigit(p_[pos_])) ++pos_;
    if (pos_ == begin) fail("is not an index", "a whole number 0, 1, 2, ... (no sign, no name) inside [ ]");
    std::size_t value = 0;
    if (std::from_chars(p_.data() + begin, p_.data() + pos_, value).ec != std::errc())
      throw FieldPathError(begin + 1, fmt::format("index {} is too large", printable(p_.substr(begin, pos_ - begin))),
                           "an index below the list's length");
    if (pos_ == p_.size() || p_[pos_] != ']') fail("follows the index where ']' must close it", "digits 0-9, then ]");
    ++pos_;
    return value;
  }

  const std::string& p_;
  std::size_t pos_ = 0;
};

std::string joinKeys(const std::vector<const scenario::FieldDoc*>& fields) {
  std::string s;
  for (const auto* f : fields) s += (s.empty() ? "" : ", ") + f->key;
  return s;
}

bool holdsFields(scenario::Kind k) {
  return k == scenario::Kind::Section || k == scenario::Kind::List || k == scenario::Kind::MaterialRef;
}

const scenario::FieldDoc& schemaField(const std::string& type, const PathStep& st) {
  auto fields = scenario::fieldsOf(type);
  for (const auto* f : fields)
    if (f->key == st.key) return *f;
  std::vector<std::string> names;
  for (const auto* f : fields) names.push_back(f->key);
  std::string near = nearestName(st.key, names);
  throw FieldPathError(st.key_position,
                       fmt::format("'{}' is not a field of section '{}'{}", printable(st.key), type,
                                   near.empty() ? "" : " (did you mean '" + near + "'?)"),
                       joinKeys(fields));
}

// Checks one step against the schema; returns the section type the next step is in.
std::string checkStep(const std::string& path, const std::string& type, const PathStep& st, bool last) {
  const scenario::FieldDoc& f = schemaField(type, st);
  const bool isList = f.kind == scenario::Kind::List;
  if (st.index && !isList)
    throw FieldPathError(st.index_position - 1, fmt::format("'{}' is not a list, so it takes no [index]", st.key),
                         fmt::format("{} without [ ]", st.key));
  if (isList && !st.index)
    throw FieldPathError(st.key_position + st.key.size(), fmt::format("'{}' is a list: name one entry", st.key),
                         fmt::format("{}[0], {}[1], ...", st.key, st.key));
  if (!last && !holdsFields(f.kind))
    throw FieldPathError(st.key_position + st.key.size(),
                         fmt::format("'{}' is a single value, so the path must end here", st.key),
                         path.substr(0, st.key_position - 1 + st.key.size()));
  if (last && f.kind != scenario::Kind::MaterialRef && holdsFields(f.kind))
    throw FieldPathError(st.key_position + st.key.size(),
                         fmt::format("'{}{}' is a section, not a single value: name one of its fields", st.key,
                                     st.index ? fmt::format("[{}]", *st.index) : std::string()),
                         joinKeys(scenario::fieldsOf(f.child)));
  return f.child;
}

}  // namespace

std::vector<PathStep> parseFieldPath(const std::string& path) { return PathScanner(path).steps(); }

std::vector<PathStep> parseScenarioFieldPath(const std::string& path) {
  auto steps = parseFieldPath(path);
  std::string type = "scenario";
  for (std::size_t i = 0; i < steps.size(); ++i) type = checkStep(path, type, steps[i], i + 1 == steps.size());
  return steps;
}

InputError fieldPathInputError(const FieldPathError& e, SourceLocation where, const std::string& field,
                               const std::string& path) {
  return InputError(std::move(where), field, path,
                    fmt::format("is not a field path of the scenario: at character {}, {}", e.position(), e.problem()),
                    e.allowed());
}

}  // namespace needlesim::study
