#pragma once
// One YAML document read from a user's file (a scenario, a study), with the checks that
// yaml-cpp leaves out: the file size, UTF-8, one document only, no duplicate key in any
// mapping, no tag other than YAML's own, and (optionally) no key that the schema does not
// know. Each problem is an InputError naming the line.
// Internal to the readers (yaml-cpp does not appear in the public headers).
#include <yaml-cpp/yaml.h>

#include <cstddef>
#include <filesystem>
#include <set>
#include <string>
#include <string_view>

namespace needlesim::scenario {

// Scenario and study files are hand-written (a few kB); bulk data goes in CSV files that they
// name. The limit keeps a wrong file from taking minutes and gigabytes before its first error.
inline constexpr std::size_t kMaxYamlBytes = std::size_t{16} << 20;

// The text of a YAML file; InputError when it cannot be read or is larger than kMaxYamlBytes
// (checked before reading). `what` names what the file should be, e.g. "a scenario file".
std::string readYamlFile(const std::filesystem::path& path, const std::string& what);

// The one document of `text`, after the checks above. `source` is the file name for messages.
// With a `root_type` (a schema section type such as "scenario"), a key that the schema does not
// know is refused as the parser reaches it, before the whole file is loaded.
YAML::Node loadYamlDocument(std::string_view text, const std::string& source, const std::string& what,
                            const std::string& root_type = "");

// The keys of the top-level mapping of `text` (empty when it is not a mapping), from the parser's
// events alone (no node tree is built), up to and including the first key of `enough`, and at
// most `max_keys` of them. Throws YAML::Exception.
std::set<std::string> topLevelKeys(std::string_view text, const std::set<std::string>& enough = {},
                                   std::size_t max_keys = 1000);

}  // namespace needlesim::scenario
