#include "needlesim/mesh/gmsh_reader.hpp"

#include <algorithm>
#include <fstream>
#include <map>

#include "needlesim/core/error.hpp"

namespace needlesim::mesh {

int VolumeMesh::nodesPerElement() const {
  if (element == "tri3") return 3;
  if (element == "quad4" || element == "tet4") return 4;
  if (element == "hex8") return 8;
  return 0;
}

namespace {

struct Block {
  int dim = 0, entity = 0, type = 0;
  std::vector<long> conn;  // node tags
};

struct GmshFile {
  std::map<std::pair<int, int>, int> physical;  // (dim, entity) -> physical tag
  std::map<long, int> nodeIndex;               // node tag -> index
  std::vector<double> X3;                      // x y z per node
  std::vector<Block> blocks;
  bool formatOk = false;
};

void readFormat(std::istream& in, const SourceLocation& where, GmshFile& g) {
  double ver;
  int ft, ds;
  in >> ver >> ft >> ds;
  if (ver < 4.0 || ft != 0)
    throw InputError(where, "$MeshFormat", std::to_string(ver), "unsupported Gmsh format",
                     "format 4.1 ASCII (gmsh -format msh41)");
  g.formatOk = true;
}

void readEntities(std::istream& in, GmshFile& g) {
  std::size_t n[4];
  in >> n[0] >> n[1] >> n[2] >> n[3];
  for (int d = 0; d < 4; ++d)
    for (std::size_t e = 0; e < n[d]; ++e) {
      int tag;
      double b;
      in >> tag;
      for (int q = 0; q < (d == 0 ? 3 : 6); ++q) in >> b;
      std::size_t np;
      in >> np;
      for (std::size_t p = 0; p < np; ++p) {
        int ph;
        in >> ph;
        if (p == 0) g.physical[{d, tag}] = ph;
      }
      if (d > 0) {
        std::size_t nb;
        in >> nb;
        for (std::size_t p = 0; p < nb; ++p) in >> b;
      }
    }
}

void readNodes(std::istream& in, GmshFile& g) {
  std::size_t nb, nn, mn, mx;
  std::string tok;
  in >> nb >> nn >> mn >> mx;
  for (std::size_t b = 0; b < nb; ++b) {
    int ed, et, par;
    std::size_t cnt;
    in >> ed >> et >> par >> cnt;
    std::vector<long> tags(cnt);
    for (auto& t : tags) in >> t;
    for (std::size_t i = 0; i < cnt; ++i) {
      double x, y, z;
      in >> x >> y >> z;
      for (int p = 0; p < par * ed; ++p) in >> tok;
      g.nodeIndex[tags[i]] = static_cast<int>(g.X3.size() / 3);
      g.X3.insert(g.X3.end(), {x, y, z});
    }
  }
}

void readElements(std::istream& in, const SourceLocation& where, GmshFile& g) {
  std::size_t nb, ne, mn, mx;
  in >> nb >> ne >> mn >> mx;
  static const std::map<int, int> npe{{1, 2}, {2, 3}, {3, 4}, {4, 4}, {5, 8}, {15, 1}};
  for (std::size_t b = 0; b < nb; ++b) {
    Block bl;
    std::size_t cnt;
    in >> bl.dim >> bl.entity >> bl.type >> cnt;
    auto it = npe.find(bl.type);
    if (it == npe.end())
      throw InputError(where, "$Elements", std::to_string(bl.type), "unsupported Gmsh element type",
                       "first-order points, lines, triangles (2), quads (3), tets (4), hexes (5)");
    for (std::size_t i = 0; i < cnt; ++i) {
      long t;
      in >> t;
      for (int q = 0; q < it->second; ++q) {
        in >> t;
        bl.conn.push_back(t);
      }
    }
    g.blocks.push_back(std::move(bl));
  }
}

// The element type name of the highest-dimension blocks (one type only).
std::string topElement(const GmshFile& g, const SourceLocation& where, int& topDim) {
  topDim = 0;
  for (const auto& b : g.blocks) topDim = std::max(topDim, b.dim);
  int type = -1;
  for (const auto& b : g.blocks)
    if (b.dim == topDim) {
      if (type >= 0 && b.type != type)
        throw InputError(where, "$Elements", std::to_string(b.type), "mixed element types in one mesh",
                         "one element type of the highest dimension");
      type = b.type;
    }
  if (topDim < 2 || type < 0)
    throw InputError(where, "$Elements", "", "no 2D or 3D elements", "triangles, quads, tets or hexes");
  return type == 2 ? "tri3" : type == 3 ? "quad4" : type == 4 ? "tet4" : "hex8";
}

VolumeMesh toVolumeMesh(const GmshFile& g, const SourceLocation& where) {
  VolumeMesh m;
  m.element = topElement(g, where, m.dim);
  for (std::size_t i = 0; i < g.X3.size() / 3; ++i)
    for (int q = 0; q < m.dim; ++q) m.X.push_back(g.X3[3 * i + q]);
  const int npe = m.nodesPerElement();
  for (const auto& b : g.blocks) {
    if (b.dim != m.dim) continue;
    auto it = g.physical.find({b.dim, b.entity});
    const int tag = it == g.physical.end() ? b.entity : it->second;
    for (long t : b.conn) {
      auto n = g.nodeIndex.find(t);
      if (n == g.nodeIndex.end())
        throw InputError(where, "$Elements", std::to_string(t), "element refers to an unknown node", "");
      m.conn.push_back(n->second);
    }
    m.tag.insert(m.tag.end(), b.conn.size() / npe, tag);
  }
  return m;
}

}  // namespace

VolumeMesh readGmsh(const std::string& path) {
  std::ifstream in(path);
  const SourceLocation where{path, 0, 0};
  if (!in) throw InputError(where, "mesh", path, "cannot open the Gmsh file", "a readable .msh file");
  GmshFile g;
  std::string tok;
  while (in >> tok) {
    if (tok == "$MeshFormat") readFormat(in, where, g);
    else if (tok == "$Entities") readEntities(in, g);
    else if (tok == "$Nodes") readNodes(in, g);
    else if (tok == "$Elements") readElements(in, where, g);
  }
  if (!g.formatOk || g.X3.empty())
    throw InputError(where, "mesh", path, "no $MeshFormat or no $Nodes section", "a Gmsh 4.1 ASCII mesh");
  return toVolumeMesh(g, where);
}

}  // namespace needlesim::mesh
