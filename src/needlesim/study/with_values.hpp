#pragma once
// A scenario's YAML with some fields set: the shared step behind the Python
// module's Scenario.with_values and the C++ API's api::Scenario::with.
#include <string>
#include <utility>
#include <vector>

#include "needlesim/core/error.hpp"

namespace needlesim::study {

// The base scenario YAML with each (field path, value text) assignment applied, as a
// study case would set them. Every path is checked against the base first; a bad one
// is an InputError at `where` naming `field` (the argument that holds the path), the
// path and the position of its bad part. The values are validated when the returned
// text is read as a scenario.
std::string withValuesYaml(const std::string& baseYaml, const std::vector<std::pair<std::string, std::string>>& values,
                           const SourceLocation& where, const std::string& field);

}  // namespace needlesim::study
