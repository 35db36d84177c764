#pragma once
// A scenario's YAML with some fields set: the shared step behind the Python
// module's Scenario.with_values and the C++ API's api::Scenario::with.
#include <filesystem>
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
//
// `dataFolder` is the folder of the scenario file the base came from (empty for a
// scenario given as text): the data files the result names by relative paths
// (tissue.geometry.file, tissue.geometry.surfaces[].file, model.mpm.measured_force,
// model.mpm.measured_markers, model.explicit.cohesive.path_file), in the base or among
// the values, are made absolute from it, as the scenario file's reader resolves them.
std::string withValuesYaml(const std::string& baseYaml, const std::vector<std::pair<std::string, std::string>>& values,
                           const SourceLocation& where, const std::string& field,
                           const std::filesystem::path& dataFolder = {});

// The folder a scenario read from `source` resolves its relative data paths from:
// the absolute folder of a file, empty for a source that is not a file ("<python>").
std::filesystem::path dataFolderOf(const std::string& source);

}  // namespace needlesim::study
