#pragma once
// The files of tissue.geometry (scenario/tissue_geometry.hpp): a Gmsh mesh or script, or closed
// surfaces meshed by Gmsh, read relative to the scenario file through mesh/gmsh_reader. Engines
// take the mesh from the scenario and read no file. Internal to the reader.
#include <filesystem>
#include <string>
#include <vector>

#include "needlesim/mesh/isolated_reader.hpp"
#include "needlesim/mesh/volume_mesh.hpp"

namespace needlesim::scenario {

// One file of tissue.geometry: the mesh or script (body empty), or a closed surface bounding
// the body named (its file stem when empty).
struct GeometryFile {
  std::string path;
  std::string body;
};

// Where a file of tissue.geometry is read from: a relative path from the scenario file's folder.
std::filesystem::path besideScenario(const std::string& path, const std::string& scenarioSource);

// Whether a path names a Gmsh mesh or script (.msh, .geo) rather than a surface.
bool isGmshMeshOrScript(const std::string& path);

// The mesh of `files` in the files' own length unit; elementSize in that unit (0 = the script's own
// sizes, or for surfaces 1/20 of the first one's bounding-box diagonal). `sizeUsed` receives the
// element size surfaces were meshed with (left as it is for a mesh or a script). Throws
// InputError naming the file for a bad one.
mesh::VolumeMesh readGeometryFiles(const std::vector<GeometryFile>& files, double elementSize,
                                   const std::string& scenarioSource, const mesh::MeshBudget& budget = {},
                                   double* sizeUsed = nullptr);

}  // namespace needlesim::scenario
