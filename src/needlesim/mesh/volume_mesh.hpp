#pragma once
// A volume mesh as the scenario layer reads it from a file, before an engine
// converts it to its own element data: first-order elements of one type, node
// coordinates in SI metres. The tissue frame of an imported mesh is the file's:
// x depth from the entry face, y across the width, z across the height.
#include <map>
#include <string>
#include <vector>

namespace needlesim::mesh {

struct VolumeMesh {
  int dim = 2;             // 2 (area elements, x y) or 3 (volume elements, x y z)
  std::string element;     // tri3, quad4 (dim 2), tet4, hex8 (dim 3)
  std::vector<double> X;   // node coordinates, dim per node (x0 y0 [z0] x1 ...), m
  std::vector<int> conn;   // nodesPerElement() node indices (0-based) per element
  std::vector<int> tag;    // per element: the physical tag of its group (else the file's entity tag)
  std::map<int, std::string> groupNames;  // physical tag -> physical name ("" when unnamed)

  int nodesPerElement() const;
  int nodes() const { return dim > 0 ? static_cast<int>(X.size()) / dim : 0; }
  int elements() const { return static_cast<int>(tag.size()); }
};

}  // namespace needlesim::mesh
