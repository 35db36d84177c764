#pragma once
// An imported tissue mesh named in a scenario (model.explicit.mesh): the path is
// resolved against the scenario file's folder and read here, so that engines get
// the mesh itself (mesh/volume_mesh.hpp) and read no file. Internal to the reader.
#include <memory>
#include <string>

#include "needlesim/mesh/volume_mesh.hpp"

namespace needlesim::scenario {

// null for an empty path; throws InputError (file, section, value) for a bad file.
std::shared_ptr<const mesh::VolumeMesh> readMeshFile(const std::string& path, const std::string& scenarioSource);

}  // namespace needlesim::scenario
