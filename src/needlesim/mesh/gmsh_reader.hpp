#pragma once
// Tissue geometry through Gmsh's library (Debian libgmsh-dev): a mesh file (.msh format 2 or 4,
// ASCII or binary, checked first by mesh/msh_check), a Gmsh script (.geo, meshed here), or closed
// surfaces (.stl, .ply, .off, .obj, .vtp read by needlesim, mesh/surface_formats; legacy .vtk by
// Gmsh) meshed into tetrahedra, into a mesh::VolumeMesh:
// the elements of the highest dimension (triangles, quadrilaterals, tetrahedra or hexahedra of
// one type; second-order elements keep their corner nodes), nodes used by them, each element's
// physical tag (else its entity tag) and the groups' names. Coordinates stay in the file's units.
// Every problem (missing, unreadable or empty file, mixed element types, inverted or degenerate
// elements, an open or self-intersecting surface) is an InputError naming the file.
#include <string>
#include <vector>

#include "needlesim/mesh/isolated_reader.hpp"
#include "needlesim/mesh/volume_mesh.hpp"

namespace needlesim::mesh {

// Gmsh runs in a sandboxed child process (isolated_reader: it cannot run programs, write or
// delete files or end this process) within `budget`; a script is first checked line by line
// (geo_script_check). A script whose largest element size makes more than budget.maxElements
// is refused before meshing, with the estimate.

// A .msh file as it is, or a .geo script meshed with Mesh.MeshSizeMax = maxElementSize (file
// units; 0 = the script's own sizes).
VolumeMesh readGmsh(const std::string& path, double maxElementSize = 0.0, const MeshBudget& budget = {});

// A closed surface bounding one body (an organ, a tumour, a vessel).
struct SurfaceBody {
  std::string path;
  std::string name;  // the group name of its tetrahedra
};

// Meshes the bodies into one conforming tetrahedral mesh with Gmsh (elements of about
// maxElementSize, file units): a body inside another is a hole of the outer one and a body of
// its own. Group tags are 1, 2, ... in the order given. maxElementSize 0: 1/20 of the first
// surface's bounding-box diagonal; `sizeUsed`, when given, receives the size meshed with.
VolumeMesh meshSurfaces(const std::vector<SurfaceBody>& bodies, double maxElementSize, const MeshBudget& budget = {},
                        double* sizeUsed = nullptr);

}  // namespace needlesim::mesh
