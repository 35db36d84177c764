#pragma once
// Field paths of studies and with_values: `insertion.profile[0].insert.speed`.
//
//   path  = step ('.' step)*
//   step  = key ['[' index ']']
//   key   = [A-Za-z_][A-Za-z0-9_]*
//   index = [0-9]+            (0-based, below the list's length in the base scenario)
//
// Each key must be a field of the scenario schema at its place (a list takes
// an index, a section takes a further key, a value ends the path).
#include <cstddef>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "needlesim/core/error.hpp"

namespace needlesim::study {

struct PathStep {
  std::string key;
  std::optional<std::size_t> index;
  std::size_t key_position = 0;    // 1-based character of the key in the path
  std::size_t index_position = 0;  // 1-based character of the index digits (when indexed)
};

// A path that breaks the grammar or the schema, or that the base scenario does
// not have: where (1-based character) and what is allowed there.
class FieldPathError : public std::invalid_argument {
 public:
  FieldPathError(std::size_t position, std::string problem, std::string allowed);
  std::size_t position() const { return position_; }
  const std::string& problem() const { return problem_; }
  const std::string& allowed() const { return allowed_; }

 private:
  std::size_t position_;
  std::string problem_, allowed_;
};

// Grammar only (no schema): throws FieldPathError.
std::vector<PathStep> parseFieldPath(const std::string& path);
// Grammar and scenario schema: throws FieldPathError naming the nearest known key.
std::vector<PathStep> parseScenarioFieldPath(const std::string& path);

// The error a user sees: `where` (file, line of the path), `field` (the key
// that holds the path, e.g. vary[0].field), the path and the bad part's position.
InputError fieldPathInputError(const FieldPathError& e, SourceLocation where, const std::string& field,
                               const std::string& path);

}  // namespace needlesim::study
