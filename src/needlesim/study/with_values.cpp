// Scenario YAML with fields set (Scenario.with_values, api::Scenario::with), its
// relative data paths made absolute from the scenario file's folder.
#include "needlesim/study/with_values.hpp"

#include <yaml-cpp/yaml.h>

#include "needlesim/study/field_path.hpp"
#include "needlesim/study/study.hpp"

namespace needlesim::study {

namespace {

// The node at `keys` below `root` (an undefined node where the path is absent); the tree
// is left as it is (const look-ups, which give an invalid node for a missing key).
YAML::Node childAt(const YAML::Node& root, std::initializer_list<const char*> keys) {
  YAML::Node node;
  node.reset(root);
  for (const char* k : keys) {
    if (!node.IsDefined() || !node.IsMap()) return YAML::Node(YAML::NodeType::Undefined);
    const YAML::Node& parent = node;
    const YAML::Node child = parent[k];
    if (!child.IsDefined()) return YAML::Node(YAML::NodeType::Undefined);
    node.reset(child);
  }
  return node;
}

// Makes the data path in `node` absolute from `folder` when it is a relative one.
bool makeAbsolute(YAML::Node node, const std::filesystem::path& folder) {
  if (!node.IsDefined() || !node.IsScalar()) return false;
  const std::filesystem::path p(node.Scalar());
  if (p.empty() || !p.is_relative()) return false;
  node = (folder / p).lexically_normal().string();
  return true;
}

std::string withAbsoluteDataPaths(const std::string& yaml, const std::filesystem::path& folder) {
  YAML::Node root = YAML::Load(yaml);
  bool changed = false;
  for (auto keys : {std::initializer_list<const char*>{"tissue", "geometry", "file"},
                    std::initializer_list<const char*>{"model", "mpm", "measured_force"},
                    std::initializer_list<const char*>{"model", "mpm", "measured_markers"},
                    std::initializer_list<const char*>{"model", "explicit", "cohesive", "path_file"}})
    changed = makeAbsolute(childAt(root, keys), folder) || changed;
  const YAML::Node surfaces = childAt(root, {"tissue", "geometry", "surfaces"});
  if (surfaces.IsDefined() && surfaces.IsSequence())
    for (const YAML::Node& s : surfaces)
      if (s.IsMap()) changed = makeAbsolute(s["file"], folder) || changed;
  if (!changed) return yaml;
  YAML::Emitter out;
  out << root;
  return std::string(out.c_str()) + "\n";
}

}  // namespace

std::filesystem::path dataFolderOf(const std::string& source) {
  if (source.empty() || source[0] == '<') return {};
  std::error_code ec;
  const std::filesystem::path absolute = std::filesystem::absolute(std::filesystem::path(source), ec);
  return ec ? std::filesystem::path() : absolute.parent_path();
}

std::string withValuesYaml(const std::string& baseYaml, const std::vector<std::pair<std::string, std::string>>& values,
                           const SourceLocation& where, const std::string& field, const std::filesystem::path& dataFolder) {
  Case c;
  for (const auto& [path, value] : values) {
    try {
      checkFieldPath(baseYaml, path);
    } catch (const FieldPathError& e) {
      throw fieldPathInputError(e, where, field, path);
    }
    c.assignments.emplace_back(path, value);
  }
  const std::string yaml = caseYaml(baseYaml, c);
  return dataFolder.empty() ? yaml : withAbsoluteDataPaths(yaml, dataFolder);
}

}  // namespace needlesim::study
