#pragma once
// The scenario schema: every field of every section, with its unit, default,
// allowed range and meaning. The reader validates against this table and
// `needlesim schema` prints it, so the two cannot drift apart.
#include <limits>
#include <string>
#include <vector>

#include "needlesim/core/error.hpp"
#include "needlesim/core/units.hpp"

namespace needlesim::scenario {

enum class Kind { Quantity, Number, String, Choice, Bool, Section, List, MaterialRef };

struct FieldDoc {
  std::string section;  // section type: scenario, tissue, block, layer, material, ...
  std::string key;
  Kind kind = Kind::Quantity;
  units::Dim dim{};
  bool required = false;
  std::string default_text;  // as a user would write it; empty = no default
  double lo = -std::numeric_limits<double>::infinity();
  double hi = std::numeric_limits<double>::infinity();
  bool lo_open = false, hi_open = false;  // open interval ends
  bool whole = false;                     // Number that counts something: no fraction allowed
  std::vector<std::string> choices;       // Choice
  std::string child;                      // Section/List: section type of the child(ren)
  std::string help;

  std::string rangeText() const;  // "> 0 Pa", "[0, 0.5)", "one of: a, b"
  bool inRange(double si) const;
};

const std::vector<FieldDoc>& schema();
// Throws needlesim::Error if the (section, key) pair is not in the schema (a programming error).
const FieldDoc& field(const std::string& section, const std::string& key);
std::vector<const FieldDoc*> fieldsOf(const std::string& section);
// The field `key` of section type `section`, or nullptr when the section has no such field.
const FieldDoc* findField(const std::string& section, const std::string& key);
// The error for a key that section type `section` does not know, listing the keys it has.
InputError unknownFieldError(SourceLocation where, const std::string& field_path, const std::string& key,
                             const std::string& section);
// The section types in the order they are documented.
std::vector<std::string> sectionTypes();

// Markdown (docs/scenario-format.md reference part) or plain text.
std::string schemaMarkdown();
std::string schemaText();

}  // namespace needlesim::scenario
