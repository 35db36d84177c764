#include "needlesim/core/error.hpp"

#include <fmt/format.h>

namespace needlesim {

std::string SourceLocation::str() const {
  std::string s = file.empty() ? std::string("<input>") : file;
  if (line > 0) s += fmt::format(":{}", line);
  if (line > 0 && column > 0) s += fmt::format(":{}", column);
  return s;
}

static std::string compose(const SourceLocation& where, const std::string& field,
                           const std::string& value, const std::string& problem,
                           const std::string& allowed) {
  std::string msg = where.str() + ": ";
  if (!field.empty()) msg += field + ": ";
  msg += problem;
  if (!value.empty()) msg += fmt::format(" (got '{}')", value);
  if (!allowed.empty()) msg += "; allowed: " + allowed;
  return msg;
}

InputError::InputError(SourceLocation where, std::string field, std::string value,
                       std::string problem, std::string allowed)
    : Error(compose(where, field, value, problem, allowed)),
      where_(std::move(where)),
      field_(std::move(field)) {}

}  // namespace needlesim
