#include "needlesim/scenario/mesh_file.hpp"

#include <algorithm>
#include <filesystem>

#include "needlesim/mesh/gmsh_reader.hpp"

namespace needlesim::scenario {

std::filesystem::path besideScenario(const std::string& path, const std::string& scenarioSource) {
  std::filesystem::path p = path;
  if (p.is_relative() && !scenarioSource.empty() && scenarioSource[0] != '<')
    p = std::filesystem::path(scenarioSource).parent_path() / p;
  return p;
}

bool isGmshMeshOrScript(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext == ".msh" || ext == ".geo";
}

mesh::VolumeMesh readGeometryFiles(const std::vector<GeometryFile>& files, double elementSize,
                                   const std::string& scenarioSource, const mesh::MeshBudget& budget,
                                   double* sizeUsed) {
  if (files.size() == 1 && files[0].body.empty() && isGmshMeshOrScript(files[0].path))
    return mesh::readGmsh(besideScenario(files[0].path, scenarioSource).string(), elementSize, budget);
  std::vector<mesh::SurfaceBody> bodies;
  for (const auto& f : files) {
    const auto p = besideScenario(f.path, scenarioSource);
    bodies.push_back({p.string(), f.body.empty() ? p.stem().string() : f.body});
  }
  return mesh::meshSurfaces(bodies, elementSize, budget, sizeUsed);
}

}  // namespace needlesim::scenario
