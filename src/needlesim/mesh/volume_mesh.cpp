#include "needlesim/mesh/volume_mesh.hpp"

namespace needlesim::mesh {

int VolumeMesh::nodesPerElement() const {
  if (element == "tri3") return 3;
  if (element == "quad4" || element == "tet4") return 4;
  if (element == "hex8") return 8;
  return 0;
}

}  // namespace needlesim::mesh
