#pragma once
// Reads and validates a scenario (YAML) into the typed Scenario, converting
// every quantity to SI. Any problem throws needlesim::InputError naming file,
// line, column, field, value and what is allowed.
#include <filesystem>
#include <string>
#include <string_view>

#include "needlesim/scenario/scenario.hpp"

namespace needlesim::scenario {

Scenario readFile(const std::filesystem::path& path);
Scenario readText(std::string_view yaml, const std::string& source_name);
// The engine a scenario file (or a results folder's summary.json) names in model.engine, from its
// YAML alone, before anything it names (meshes, CSVs) is read: ModelSpec's default when it names
// none, "" when the file cannot be read (readFile then says why).
std::string engineNamedIn(const std::filesystem::path& path);
// The built-in default: examples/gelatin_18G_3mms.yaml compiled into the binary.
Scenario defaultScenario();

}  // namespace needlesim::scenario
