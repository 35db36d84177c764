#include "needlesim/mesh/gmsh_reader.hpp"

#include <gmsh.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fmt/format.h>
#include <map>
#include <set>

#include "needlesim/core/error.hpp"
#include "needlesim/mesh/boundary.hpp"
#include "needlesim/mesh/closed_surface.hpp"
#include "needlesim/mesh/geo_script_check.hpp"
#include "needlesim/mesh/isolated_reader.hpp"
#include "needlesim/mesh/msh_check.hpp"
#include "needlesim/mesh/surface_checks.hpp"
#include "needlesim/mesh/surface_formats.hpp"
#include "needlesim/mesh/vtp_reader.hpp"

namespace needlesim::mesh {

namespace {

// Gmsh in the sandboxed child (isolated_reader): one model per process, one thread, quiet.
class GmshSession {
 public:
  GmshSession() {
    gmsh::initialize(0, nullptr, false);
    gmsh::option::setNumber("General.Terminal", 0);
    gmsh::option::setNumber("General.Verbosity", 1);
    gmsh::option::setNumber("General.NumThreads", 1);
    gmsh::option::setNumber("Mesh.MeshSizeMax", 1e22);
  }
};

InputError geometryError(const std::string& path, const std::string& problem, const std::string& allowed) {
  return InputError(SourceLocation{path, 0, 0}, "tissue.geometry", std::filesystem::path(path).filename().string(),
                    problem, allowed);
}

// The file's absolute path (taken in the parent: the child works in its own empty folder).
std::string absolute(const std::string& path) { return std::filesystem::absolute(path).string(); }

// Runs a Gmsh call, turning Gmsh's own errors into an InputError naming the file.
template <class F>
void gmshCall(const std::string& path, const std::string& doing, const std::string& allowed, F&& f) {
  std::string message;
  try {
    f();
    return;
  } catch (const std::string& s) {
    message = s;
  } catch (const std::exception& e) {
    message = e.what();
  } catch (...) {
    gmsh::logger::getLastError(message);
  }
  throw geometryError(path, fmt::format("Gmsh could not {}: {}", doing, message.empty() ? "no reason given" : message),
                      allowed);
}

// Corner-node element family of each Gmsh element type (second order keeps its corners).
struct Family {
  const char* name;
  int dim, corners;
};
const std::map<int, Family>& families() {
  static const std::map<int, Family> f = {
      {2, {"tri3", 2, 3}},  {9, {"tri3", 2, 3}},   {3, {"quad4", 2, 4}}, {10, {"quad4", 2, 4}}, {16, {"quad4", 2, 4}},
      {4, {"tet4", 3, 4}},  {11, {"tet4", 3, 4}},  {5, {"hex8", 3, 8}},  {12, {"hex8", 3, 8}},  {17, {"hex8", 3, 8}}};
  return f;
}

std::string typeName(int gmshType) {
  std::string name;
  int dim = 0, order = 0, nodes = 0, primary = 0;
  std::vector<double> local;
  gmsh::model::mesh::getElementProperties(gmshType, name, dim, order, nodes, local, primary);
  return name;
}

// Elements of dimension `dim` of every entity, with their group tags, into `m`.
void collectElements(const std::string& path, int dim, VolumeMesh& m, std::vector<std::size_t>& nodeTags) {
  gmsh::vectorpair entities;
  gmsh::model::getEntities(entities, dim);
  std::set<std::string> seenTypes;
  for (const auto& [d, entity] : entities) {
    std::vector<int> groups;
    gmsh::model::getPhysicalGroupsForEntity(d, entity, groups);
    const int tag = groups.empty() ? entity : groups.front();
    if (!groups.empty()) {
      std::string name;
      gmsh::model::getPhysicalName(d, tag, name);
      m.groupNames[tag] = name;
    }
    std::vector<int> types;
    std::vector<std::vector<std::size_t>> elementTags, elementNodes;
    gmsh::model::mesh::getElements(types, elementTags, elementNodes, d, entity);
    for (std::size_t k = 0; k < types.size(); ++k) {
      const auto family = families().find(types[k]);
      if (family == families().end())
        throw geometryError(path, fmt::format("has elements of type {} (Gmsh type {})", typeName(types[k]), types[k]),
                            "triangles, quadrilaterals, tetrahedra or hexahedra, first or second order");
      seenTypes.insert(family->second.name);
      m.element = family->second.name;
      const std::size_t per = elementNodes[k].size() / elementTags[k].size();
      for (std::size_t e = 0; e < elementTags[k].size(); ++e) {
        for (int a = 0; a < family->second.corners; ++a) nodeTags.push_back(elementNodes[k][e * per + a]);
        m.tag.push_back(tag);
      }
    }
  }
  if (seenTypes.size() > 1)
    throw geometryError(path, fmt::format("mixes {} elements in one mesh", fmt::join(seenTypes, " and ")),
                        "one element type (e.g. all tetrahedra: Gmsh without Mesh.RecombineAll)");
}

int topDimension() {
  for (int d = 3; d >= 2; --d) {
    std::vector<int> types;
    std::vector<std::vector<std::size_t>> tags, nodes;
    gmsh::model::mesh::getElements(types, tags, nodes, d, -1);
    for (const auto& t : tags)
      if (!t.empty()) return d;
  }
  return 0;
}

// The model's mesh of its highest dimension; the nodes its elements use, numbered 0.. in the file's order.
VolumeMesh extractMesh(const std::string& path) {
  VolumeMesh m;
  m.dim = topDimension();
  if (m.dim == 0)
    throw geometryError(path, "holds no triangles, quadrilaterals, tetrahedra or hexahedra",
                        "a 2D or 3D mesh (gmsh -2 or -3), or a script that makes one");
  std::vector<std::size_t> nodeTags;
  collectElements(path, m.dim, m, nodeTags);
  std::vector<std::size_t> allTags;
  std::vector<double> coord, parametric;
  gmsh::model::mesh::getNodes(allTags, coord, parametric, -1, -1, true, false);
  // nodes used by the elements, in the file's order (0-based)
  std::map<std::size_t, int> index;
  for (std::size_t t : nodeTags) index.emplace(t, -1);
  for (std::size_t i = 0; i < allTags.size(); ++i) {
    const auto used = index.find(allTags[i]);
    if (used == index.end() || used->second >= 0) continue;
    used->second = m.nodes();
    const double* p = &coord[3 * i];
    if (m.dim == 2 && std::abs(p[2]) > 1e-12 * (1.0 + std::abs(p[0]) + std::abs(p[1])))
      throw geometryError(path, fmt::format("is a 2D mesh with node {} at z = {:g}", allTags[i], p[2]),
                          "a 2D mesh in the plane z = 0 (x depth, y across)");
    for (int k = 0; k < m.dim; ++k) m.X.push_back(p[k]);
  }
  for (std::size_t t : nodeTags) {
    const int n = index.at(t);
    if (n < 0) throw geometryError(path, fmt::format("an element uses node {}, which has no coordinates", t), "a complete mesh");
    m.conn.push_back(n);
  }
  return m;
}

// Node order of element e reversed in orientation (a mirrored element).
void flip(VolumeMesh& m, int e) {
  int* c = &m.conn[static_cast<std::size_t>(e) * m.nodesPerElement()];
  if (m.element == "hex8") {
    for (int a = 0; a < 4; ++a) std::swap(c[a], c[a + 4]);
  } else if (m.element == "quad4") {
    std::swap(c[1], c[3]);
  } else {
    std::swap(c[1], c[2]);
  }
}

// Every element positively oriented: a mesh whose elements are all mirrored is turned round;
// a degenerate element, or one inverted against the rest, is refused.
void checkOrientation(const std::string& path, VolumeMesh& m) {
  double largest = 0.0;
  std::vector<double> measure(m.elements());
  for (int e = 0; e < m.elements(); ++e) largest = std::max(largest, std::abs(measure[e] = elementMeasure(m, e)));
  const int negative = static_cast<int>(std::count_if(measure.begin(), measure.end(), [](double v) { return v < 0; }));
  const bool mirrored = negative * 2 > m.elements();
  const char* what = m.dim == 2 ? "area" : "volume";
  for (int e = 0; e < m.elements(); ++e) {
    const double v = mirrored ? -measure[e] : measure[e];
    if (std::abs(v) <= 1e-10 * largest)
      throw geometryError(path, fmt::format("element {} ({}) is degenerate: its {} is {:.3g} against {:.3g} for the largest",
                                            e + 1, m.element, what, std::abs(v), largest),
                          "elements with a non-zero " + std::string(what));
    if (v < 0)
      throw geometryError(path, fmt::format("element {} ({}) is inverted: its nodes turn the other way from the rest of the mesh",
                                            e + 1, m.element),
                          "consistently oriented elements");
    if (mirrored) flip(m, e);
  }
}

void requireFile(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec))
    throw geometryError(path, std::filesystem::exists(path, ec) ? "is not a file" : "does not exist",
                        "a readable mesh, script or surface file (relative paths: from the scenario's folder)");
}

bool isScript(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext == ".geo";
}


// Elements of about size h filling `measure` (a volume in 3D, an area in 2D): regular
// tetrahedra or triangles of edge h.
double elementsAtSize(double measure, int dim, double h) {
  return dim == 3 ? measure / (h * h * h / (6.0 * std::sqrt(2.0))) : measure / (std::sqrt(3.0) / 4.0 * h * h);
}

// The model's volume (3D) or area (2D): OpenCASCADE's masses where the script used that
// kernel, else its bounding box.
double modelMeasure(int dim) {
  double measure = 0.0;
  try {
    gmsh::vectorpair entities;
    gmsh::model::occ::getEntities(entities, dim);
    for (const auto& [d, tag] : entities) {
      double mass = 0.0;
      gmsh::model::occ::getMass(d, tag, mass);
      measure += std::abs(mass);
    }
  } catch (...) {
    measure = 0.0;
  }
  if (measure > 0.0) return measure;
  double x0, y0, z0, x1, y1, z1;
  gmsh::model::getBoundingBox(-1, -1, x0, y0, z0, x1, y1, z1);
  return dim == 3 ? (x1 - x0) * (y1 - y0) * (z1 - z0) : (x1 - x0) * (y1 - y0);
}

// `verb` "holds", "made" or "would make about"; h the element size asked (0: none).
[[noreturn]] void refuseElementCount(const std::string& path, const std::string& verb, double n, int dim, double h,
                                     const MeshBudget& budget) {
  const double larger = h > 0 ? h * std::pow(n / budget.maxElements, 1.0 / dim) : 0.0;
  throw geometryError(path, fmt::format("{} {:.3g} elements{}, more than tissue.geometry.max_elements ({:g})", verb, n,
                                        h > 0 ? fmt::format(" at an element size of {:g} (file units)", h) : "",
                                        budget.maxElements),
                      larger > 0 ? fmt::format("a larger tissue.geometry.element_size (or Mesh.MeshSizeMax): about {:.3g} "
                                               "(file units) or more for this budget; or a larger max_elements", larger)
                                 : "a coarser mesh, or a larger tissue.geometry.max_elements");
}

// Before meshing a script: the elements its largest element size (Mesh.MeshSizeMax, set by the
// script or tissue.geometry.element_size) makes at least, against the budget.
void checkEstimate(const std::string& path, const MeshBudget& budget) {
  double largest = 0.0, factor = 1.0;
  gmsh::option::getNumber("Mesh.MeshSizeMax", largest);
  gmsh::option::getNumber("Mesh.MeshSizeFactor", factor);
  const int dim = gmsh::model::getDimension();
  if (largest >= 1e21 || dim < 2) return;  // the script's own sizes: counted after meshing
  const double h = largest * factor;
  const double n = elementsAtSize(modelMeasure(dim), dim, h);
  if (n > budget.maxElements)
    refuseElementCount(path, "would make about", n, dim, h, budget);
}

// Before meshing a script: its geometry lies at finite coordinates (a point at 1e400 would have
// Gmsh fill memory up to the child's cap with elements of the script's own size).
void checkFiniteBounds(const std::string& path) {
  double b[6] = {0, 0, 0, 0, 0, 0};
  gmsh::model::getBoundingBox(-1, -1, b[0], b[1], b[2], b[3], b[4], b[5]);
  if (!isPlausibleVertex(b) || !isPlausibleVertex(b + 3))  // the limit every mesh's nodes are held to
    throw geometryError(path,
                        fmt::format("its geometry reaches ({:g}, {:g}, {:g}) to ({:g}, {:g}, {:g}) (file units)", b[0],
                                    b[1], b[2], b[3], b[4], b[5]),
                        fmt::format("a script whose points lie at finite coordinates (at most {:g} in size, file units)",
                                    kLargestCoordinate));
}

// Runs in the sandboxed child: the file opened, a script meshed, the mesh checked.
VolumeMesh openAndMesh(const std::string& path, const std::string& file, double maxElementSize, const MeshBudget& budget) {
  GmshSession session;
  gmshCall(path, "read it", "a Gmsh .msh (format 2 or 4, ASCII or binary) or .geo script", [&] { gmsh::open(file); });
  if (isScript(path)) {
    if (maxElementSize > 0) gmsh::option::setNumber("Mesh.MeshSizeMax", maxElementSize);
    gmsh::option::setNumber("General.NumThreads", 1);
    checkFiniteBounds(path);
    checkEstimate(path, budget);
    gmshCall(path, "mesh the script", "a script whose geometry Gmsh can mesh", [&] {
      gmsh::model::mesh::generate(gmsh::model::getDimension());
    });
  }
  VolumeMesh m = extractMesh(path);
  checkMeshCoordinates(path, m);
  if (m.elements() > budget.maxElements)
    refuseElementCount(path, isScript(path) ? "made" : "holds", m.elements(), m.dim, 0.0, budget);
  checkOrientation(path, m);
  return m;
}

}  // namespace

VolumeMesh readGmsh(const std::string& path, double maxElementSize, const MeshBudget& budget) {
  requireFile(path);
  if (gmshReadsAsScript(path)) checkGeoScript(path);
  if (isMsh(path)) checkMshFile(path);
  const std::string file = absolute(path);
  return decodeMesh(runIsolated(path, budget, [&] { return encodeMesh(openAndMesh(path, file, maxElementSize, budget)); }));
}

namespace {

TriangleSurface closedOrRefused(const std::string& path, TriangleSurface s) {
  if (s.triangles() == 0)
    throw geometryError(path, "holds no triangles", "a closed triangulated surface (quadrilaterals: split them first)");
  if (const std::string open = openEdge(s); !open.empty())
    throw geometryError(path, "is not a closed surface: " + open,
                        "a closed (watertight) surface, every edge shared by exactly two triangles");
  return s;
}

// A surface file's triangles (needlesim's own readers; Gmsh's for legacy VTK), refused when open
// or in a format Gmsh's library would misread.
TriangleSurface readSurface(const std::string& path, const MeshBudget& budget) {
  requireFile(path);
  if (const auto bad = surfaceFormatProblem(path)) throw geometryError(path, bad->problem, bad->allowed);
  if (auto own = readOwnSurfaceFormat(path)) return closedOrRefused(path, std::move(*own));
  if (gmshReadsAsScript(path)) checkGeoScript(path);  // Gmsh would read it as a script
  const std::string file = absolute(path);
  return closedOrRefused(path, decodeSurface(runIsolated(path, budget, [&] {
                           GmshSession session;
                           gmshCall(path, "read it", "a closed surface in legacy VTK 4.2 or older (or .stl, .ply, .off, .obj, .vtp)",
                                    [&] { gmsh::merge(file); });
                           TriangleSurface s;
                           std::vector<std::size_t> tags, triangleTags, triangleNodes;
                           std::vector<double> parametric;
                           gmsh::model::mesh::getNodes(tags, s.xyz, parametric, -1, -1, true, false);
                           std::map<std::size_t, int> index;
                           for (std::size_t i = 0; i < tags.size(); ++i) index[tags[i]] = static_cast<int>(i);
                           gmsh::model::mesh::getElementsByType(2, triangleTags, triangleNodes);
                           for (std::size_t t : triangleNodes) s.tri.push_back(index.at(t));
                           return encodeSurface(s);
                         })));
}

// The volume a closed surface encloses (divergence theorem over its triangles).
double enclosedVolume(const TriangleSurface& s) {
  double v = 0.0;
  for (int t = 0; t < s.triangles(); ++t) {
    const double* a = &s.xyz[3 * static_cast<std::size_t>(s.tri[3 * t])];
    const double* b = &s.xyz[3 * static_cast<std::size_t>(s.tri[3 * t + 1])];
    const double* c = &s.xyz[3 * static_cast<std::size_t>(s.tri[3 * t + 2])];
    v += a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) + a[2] * (b[0] * c[1] - b[1] * c[0]);
  }
  return std::abs(v) / 6.0;
}

// The tetrahedra of about maxElementSize filling the outermost bodies, against the budget.
void checkSurfaceEstimate(const std::vector<SurfaceBody>& bodies, const std::vector<TriangleSurface>& surfaces,
                          const std::vector<std::vector<int>>& holes, double maxElementSize, const MeshBudget& budget) {
  std::vector<char> inner(surfaces.size(), 0);
  for (const auto& inside : holes)
    for (int h : inside) inner[h] = 1;
  double volume = 0.0;
  for (std::size_t b = 0; b < surfaces.size(); ++b)
    if (!inner[b]) volume += enclosedVolume(surfaces[b]);
  const double n = elementsAtSize(volume, 3, maxElementSize);
  if (n > budget.maxElements)
    refuseElementCount(bodies[0].path, "would make about", n, 3, maxElementSize, budget);
}

// The surfaces as discrete Gmsh surfaces whose triangles bound the tetrahedra; one surface loop
// per body.
std::vector<int> addSurfaceLoops(const std::vector<TriangleSurface>& surfaces) {
  std::vector<int> loops;
  std::size_t next = 1;
  for (const auto& s : surfaces) {
    const int entity = gmsh::model::addDiscreteEntity(2);
    std::vector<std::size_t> tags(s.xyz.size() / 3), nodes;
    for (std::size_t i = 0; i < tags.size(); ++i) tags[i] = next + i;
    for (int v : s.tri) nodes.push_back(next + static_cast<std::size_t>(v));
    gmsh::model::mesh::addNodes(2, entity, tags, s.xyz);
    gmsh::model::mesh::addElementsByType(entity, 2, {}, nodes);
    next += tags.size();
    loops.push_back(gmsh::model::geo::addSurfaceLoop({entity}));
  }
  return loops;
}

}  // namespace

VolumeMesh meshSurfaces(const std::vector<SurfaceBody>& bodies, double maxElementSize, const MeshBudget& budget,
                        double* sizeUsed) {
  std::vector<TriangleSurface> surfaces;
  for (const auto& b : bodies) surfaces.push_back(readSurface(b.path, budget));
  for (std::size_t a = 0; a < surfaces.size(); ++a)
    for (std::size_t b = 0; b < surfaces.size(); ++b)
      if (a != b && placement(surfaces[a], surfaces[b]) == Placement::Crossing)
        throw geometryError(bodies[b].path, fmt::format("crosses the surface of {}: some of its vertices lie inside it, some outside",
                                                        bodies[a].path),
                            "closed surfaces that cross neither themselves nor each other (a body inside another, or apart)");
  const auto holes = directlyInside(surfaces);
  // Gmsh keeps a discrete surface's triangles: split them down to the element size first
  if (maxElementSize <= 0) maxElementSize = boxDiagonal(surfaces[0]) / 20;
  if (sizeUsed) *sizeUsed = maxElementSize;
  checkSurfaceEstimate(bodies, surfaces, holes, maxElementSize, budget);
  constexpr std::size_t kMostTriangles = 2'000'000;
  for (std::size_t b = 0; b < surfaces.size(); ++b) {
    const double splits = std::ceil(std::log2(std::max(1.0, longestEdge(surfaces[b]) / maxElementSize)));
    if (surfaces[b].tri.size() / 3 * std::pow(4.0, splits) > kMostTriangles)
      throw geometryError(bodies[b].path, fmt::format("would need {:.3g} surface triangles at an element size of {:g}",
                                                      surfaces[b].tri.size() / 3 * std::pow(4.0, splits), maxElementSize),
                          "a larger tissue.geometry.element_size");
    surfaces[b] = refined(surfaces[b], maxElementSize);
  }
  std::string all = bodies[0].path;
  for (std::size_t b = 1; b < bodies.size(); ++b) all += ", " + bodies[b].path;
  return decodeMesh(runIsolated(all, budget, [&] {
    GmshSession session;
    gmshCall(all, "mesh the surfaces into tetrahedra", "closed surfaces that cross neither themselves nor each other", [&] {
      const auto loops = addSurfaceLoops(surfaces);
      for (std::size_t b = 0; b < bodies.size(); ++b) {
        std::vector<int> boundary{loops[b]};
        for (int h : holes[b]) boundary.push_back(loops[h]);
        const int volume = gmsh::model::geo::addVolume(boundary);
        gmsh::model::geo::synchronize();
        const int group = gmsh::model::addPhysicalGroup(3, {volume}, static_cast<int>(b) + 1);
        gmsh::model::setPhysicalName(3, group, bodies[b].name);
      }
      gmsh::option::setNumber("Mesh.MeshSizeMax", maxElementSize);
      gmsh::model::mesh::generate(3);
    });
    VolumeMesh m = extractMesh(all);
    if (m.elements() > budget.maxElements) refuseElementCount(all, "made", m.elements(), 3, 0.0, budget);
    checkOrientation(all, m);
    return encodeMesh(m);
  }));
}

}  // namespace needlesim::mesh
