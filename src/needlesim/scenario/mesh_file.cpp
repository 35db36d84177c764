#include "needlesim/scenario/mesh_file.hpp"

#include <filesystem>

#include "needlesim/mesh/gmsh_reader.hpp"

namespace needlesim::scenario {

std::shared_ptr<const mesh::VolumeMesh> readMeshFile(const std::string& path, const std::string& scenarioSource) {
  if (path.empty()) return nullptr;
  std::filesystem::path p = path;
  if (p.is_relative() && !scenarioSource.empty() && scenarioSource[0] != '<')
    p = std::filesystem::path(scenarioSource).parent_path() / p;
  return std::make_shared<const mesh::VolumeMesh>(mesh::readGmsh(p.string()));
}

}  // namespace needlesim::scenario
