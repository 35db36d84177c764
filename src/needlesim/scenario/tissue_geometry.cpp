#include "needlesim/scenario/tissue_geometry.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fmt/format.h>
#include <Eigen/Geometry>
#include <limits>
#include <map>
#include <numbers>

#include "needlesim/core/nearest_name.hpp"
#include "needlesim/mesh/boundary.hpp"
#include "needlesim/needle/insertion_frame.hpp"
#include "needlesim/scenario/mesh_file.hpp"

namespace needlesim::scenario {

namespace {

using mesh::Point;

// Metres per unit of tissue.geometry.unit.
double metresPer(const std::string& unit) {
  static const std::map<std::string, double> scale = {{"m", 1.0}, {"cm", 1e-2}, {"mm", 1e-3}, {"um", 1e-6}};
  return scale.at(unit);
}

std::string mm(double metres) { return fmt::format("{:.6g} mm", metres * 1e3); }
std::string mmPoint(const double* p) { return fmt::format("({:.4g}, {:.4g}, {:.4g}) mm", p[0] * 1e3, p[1] * 1e3, p[2] * 1e3); }

// A file of tissue.geometry that is not there: the scenario's line and the absolute path looked at.
void requireGeometryFile(const Section& at, const std::string& path, const std::string& source) {
  std::error_code ec;
  const std::filesystem::path p = besideScenario(path, source);
  if (std::filesystem::is_regular_file(p, ec)) return;
  const std::string looked = std::filesystem::absolute(p, ec).lexically_normal().string();
  throw at.error("file", path,
                 fmt::format("{}: looked for {}", std::filesystem::exists(p, ec) ? "is not a file" : "does not exist",
                             looked),
                 "a readable mesh, script or surface file; a relative path is read from the scenario file's folder");
}

// The file or the surfaces of tissue.geometry, read in the file's units.
// Surfaces meshed at the default size record that size (tissue.geometry.element_size).
mesh::VolumeMesh importFiles(Section& g, const std::string& source, double elementSizeInFileUnits, std::string& named,
                             double scale) {
  std::vector<GeometryFile> sources;
  const auto surfaces = g.list("surfaces");
  if (g.has("file") == !surfaces.empty())
    throw g.error("file", "", "give either file or surfaces", "file: a mesh, script or surface; or surfaces: a list");
  if (g.has("file")) {
    sources.push_back({g.text("file"), ""});
    requireGeometryFile(g, sources.back().path, source);
  }
  for (std::size_t i = 0; i < surfaces.size(); ++i) {
    Section s = g.element(surfaces[i], "surfaces", i);
    sources.push_back({s.text("file"), s.text("body")});
    if (sources.back().body.empty()) s.remember("body", std::filesystem::path(sources.back().path).stem().string());
    requireGeometryFile(s, sources.back().path, source);
  }
  for (std::size_t i = 0; i < surfaces.size(); ++i)
    if (isGmshMeshOrScript(sources[i].path))
      throw g.error("surfaces", sources[i].path, "is a Gmsh mesh or script, not a surface",
                    "surfaces: closed surfaces (.stl, .ply, .vtk, .off, .obj); a .msh or .geo goes under file");
  if (g.has("element_size") && sources.size() == 1 && sources[0].path.ends_with(".msh"))
    throw g.error("element_size", g.raw("element_size").Scalar(), "has no meaning for a .msh file: its elements are given",
                  "no element_size; or a .geo script or surfaces, which Gmsh meshes");
  for (const auto& s : sources) named += (named.empty() ? "" : ", ") + s.path;
  const mesh::MeshBudget budget{g.number("max_elements"), g.number("max_mesh_time"),
                                g.number("max_mesh_memory_mib") * 1024.0 * 1024.0};
  double used = 0.0;
  mesh::VolumeMesh m = readGeometryFiles(sources, elementSizeInFileUnits, source, budget, &used);
  if (!g.has("element_size") && used > 0.0) g.rememberNumber("element_size", used * scale);
  return m;
}

// Rotation about x, then y, then z of the tissue frame (right hand).
Eigen::Matrix3d rotation(double ax, double ay, double az) {
  using Eigen::AngleAxisd, Eigen::Vector3d;
  return (AngleAxisd(az, Vector3d::UnitZ()) * AngleAxisd(ay, Vector3d::UnitY()) * AngleAxisd(ax, Vector3d::UnitX()))
      .toRotationMatrix();
}

// Scaled to metres, rotated, then shifted.
void place(mesh::VolumeMesh& m, double scale, const Eigen::Matrix3d& R, const Eigen::Vector3d& shift) {
  const int d = m.dim;
  for (int n = 0; n < m.nodes(); ++n) {
    Eigen::Vector3d p = Eigen::Vector3d::Zero();
    for (int i = 0; i < d; ++i) p[i] = scale * m.X[static_cast<std::size_t>(n) * d + i];
    const Eigen::Vector3d q = R * p + shift;
    for (int i = 0; i < d; ++i) m.X[static_cast<std::size_t>(n) * d + i] = q[i];
  }
}

void boundingBox(ImportedGeometry& g) {
  const auto& m = *g.mesh;
  for (int i = 0; i < 3; ++i) g.lo[i] = g.hi[i] = 0.0;
  for (int i = 0; i < m.dim; ++i) {
    g.lo[i] = std::numeric_limits<double>::infinity();
    g.hi[i] = -g.lo[i];
    for (int n = 0; n < m.nodes(); ++n) {
      g.lo[i] = std::min(g.lo[i], m.X[static_cast<std::size_t>(n) * m.dim + i]);
      g.hi[i] = std::max(g.hi[i], m.X[static_cast<std::size_t>(n) * m.dim + i]);
    }
  }
}

// A unit slip (a mm file read as m) makes a body metres across or a hundredth of a millimetre:
// refused, naming the unit that gives a tissue-sized body (the block's plausibility bounds).
void checkSize(const ImportedGeometry& g, Section& geo, const std::string& unit) {
  double extent = 0.0;
  for (int i = 0; i < 3; ++i) extent = std::max(extent, g.hi[i] - g.lo[i]);
  constexpr double kSmallest = 1e-3, kLargest = 1.0;  // m: tissue samples to a torso (problem_sections.cpp kMaxBlockSide)
  if (extent >= kSmallest && extent <= kLargest) return;
  std::string better;
  for (const char* u : {"m", "cm", "mm", "um"}) {
    const double e = extent / metresPer(unit) * metresPer(u);
    if (e >= kSmallest && e <= kLargest) better += fmt::format("{}with unit: {} it is {}", better.empty() ? "" : "; ", u, mm(e));
  }
  throw geo.error("unit", unit,
                  fmt::format("makes the geometry {} across; a tissue is between 1 mm and 1 m{}", mm(extent),
                              better.empty() ? "" : " (" + better + ")"),
                  "the length unit the file's coordinates are written in: m, cm, mm or um");
}

}  // namespace

std::shared_ptr<ImportedGeometry> placeGeometry(Section& g, const std::string& source, TissueSpec& T) {
  auto geo = std::make_shared<ImportedGeometry>();
  const std::string unit = g.choice("unit");
  const double scale = metresPer(unit);
  const auto size = g.optNumber("element_size");
  mesh::VolumeMesh m = importFiles(g, source, size ? *size / scale : 0.0, geo->file, scale);
  Section r = g.sub("rotate"), t = g.sub("translate");
  const double shift[3] = {t.number("x"), t.number("y"), t.number("z")};
  if (m.dim == 2 && (r.number("x") != 0.0 || r.number("y") != 0.0 || shift[2] != 0.0))
    throw g.error("rotate", "", "turns a 2D mesh out of its plane", "rotate.z and translate.x, .y only for a 2D mesh");
  place(m, scale, rotation(r.number("x"), r.number("y"), r.number("z")), Eigen::Vector3d(shift[0], shift[1], shift[2]));
  geo->mesh = std::make_shared<const mesh::VolumeMesh>(std::move(m));
  boundingBox(*geo);
  checkSize(*geo, g, unit);
  if (geo->lo[0] < -1e-9 * (geo->hi[0] - geo->lo[0]))
    throw g.error("translate", fmt::format("x = {}", mm(shift[0])),
                  fmt::format("places the geometry in front of the entry plane x = 0, where the needle starts "
                              "(it reaches x = {})", mm(geo->lo[0])),
                  fmt::format("translate.x at least {} larger", mm(-geo->lo[0])));
  T.length = geo->hi[0];
  T.width = 2.0 * std::max(std::abs(geo->lo[1]), std::abs(geo->hi[1]));
  T.height = 2.0 * std::max(std::abs(geo->lo[2]), std::abs(geo->hi[2]));
  return geo;
}

std::set<std::string> groupNames(const ImportedGeometry& geometry) {
  std::set<std::string> names;
  for (const auto& [tag, name] : geometry.mesh->groupNames)
    if (!name.empty()) names.insert(name);
  return names;
}

namespace {

std::string listed(const std::vector<std::string>& names) {
  std::string s;
  for (const auto& n : names) s += (s.empty() ? "" : ", ") + n;
  return s.empty() ? "(none)" : s;
}

// The region of each group tag of the mesh (see mapRegions).
std::map<int, int> regionOfTag(const ImportedGeometry& g, const TissueSpec& T, Section& t) {
  std::vector<std::string> known;
  for (const auto& L : T.layers) known.push_back(L.name);
  for (const auto& I : T.inclusions)
    if (I.shape == InclusionSpec::Shape::Mesh) known.push_back(I.name);
  const int layers = static_cast<int>(T.layers.size());
  std::map<int, int> region;
  for (int tag : g.mesh->tag) {
    if (region.count(tag)) continue;
    const auto named = g.mesh->groupNames.find(tag);
    const std::string name = named == g.mesh->groupNames.end() ? "" : named->second;
    const auto at = std::find(known.begin(), known.end(), name);
    if (!name.empty() && at != known.end()) {
      const int k = static_cast<int>(at - known.begin());
      region[tag] = k < layers ? k : layers + static_cast<int>(std::find_if(T.inclusions.begin(), T.inclusions.end(),
                                                                             [&](const InclusionSpec& I) {
                                                                               return I.name == name;
                                                                             }) - T.inclusions.begin());
    } else if (layers == 1) {
      region[tag] = 0;
    } else {
      const std::string near = nearestName(name, known);
      throw t.error("geometry", name.empty() ? fmt::format("group {}", tag) : name,
                    fmt::format("this group of {} is neither a layer nor an inclusion of the scenario{}", g.file,
                                near.empty() ? "" : " (did you mean " + near + "?)"),
                    "tissue.layers and tissue.inclusions named after the groups; the scenario names: " + listed(known));
    }
  }
  return region;
}

// Volume-weighted centroid, equivalent radius and the most common layer around a mesh inclusion.
void describeInclusion(const ImportedGeometry& g, InclusionSpec& I, int r, const TissueSpec& T) {
  const auto& m = *g.mesh;
  double volume = 0.0, c[3] = {0, 0, 0};
  std::vector<char> member(m.nodes(), 0);
  const int npe = m.nodesPerElement();
  for (int e = 0; e < m.elements(); ++e) {
    if (g.region[e] != r) continue;
    const double v = std::abs(mesh::elementMeasure(m, e));
    const Point p = mesh::elementCentroid(m, e);
    for (int i = 0; i < 3; ++i) c[i] += v * p[i];
    volume += v;
    for (int a = 0; a < npe; ++a) member[m.conn[static_cast<std::size_t>(e) * npe + a]] = 1;
  }
  I.x = c[0] / volume, I.y = c[1] / volume, I.z = c[2] / volume;
  I.radius = m.dim == 3 ? std::cbrt(3.0 * volume / (4.0 * std::numbers::pi)) : std::sqrt(volume / std::numbers::pi);
  std::map<int, int> around;  // layer -> elements touching the inclusion
  for (int e = 0; e < m.elements(); ++e)
    if (g.region[e] < static_cast<int>(T.layers.size()))
      for (int a = 0; a < npe; ++a)
        if (member[m.conn[static_cast<std::size_t>(e) * npe + a]]) {
          ++around[g.region[e]];
          break;
        }
  const int layer = around.empty() ? 0
                                   : std::max_element(around.begin(), around.end(), [](auto& a, auto& b) {
                                       return a.second < b.second;
                                     })->first;
  if (std::isnan(I.friction_coefficient)) I.friction_coefficient = T.layers[layer].friction.coefficient;
  if (std::isnan(I.toughness)) I.toughness = T.layers[layer].toughness;
}

// The layer of the element whose centroid lies nearest to a placed inclusion's centre: the
// layer around it.
int layerAround(const ImportedGeometry& g, const InclusionSpec& I, int layers) {
  const auto& m = *g.mesh;
  int best = 0;
  double bestDistance = std::numeric_limits<double>::infinity();
  for (int e = 0; e < m.elements(); ++e) {
    if (g.region[e] >= layers) continue;
    const Point p = mesh::elementCentroid(m, e);
    const double d = std::hypot(p[0] - I.x, p[1] - I.y, p[2] - I.z);
    if (d < bestDistance) bestDistance = d, best = g.region[e];
  }
  return best;
}

}  // namespace

void mapRegions(ImportedGeometry& geometry, TissueSpec& T, Section& t) {
  const auto region = regionOfTag(geometry, T, t);
  geometry.region.clear();
  for (int tag : geometry.mesh->tag) geometry.region.push_back(region.at(tag));
  std::vector<int> count(T.layers.size() + T.inclusions.size(), 0);
  for (int r : geometry.region) ++count[r];
  const auto names = groupNames(geometry);
  const std::vector<std::string> groups(names.begin(), names.end());
  for (std::size_t i = 0; i < T.layers.size(); ++i)
    if (count[i] == 0)
      throw t.error("layers", T.layers[i].name,
                    fmt::format("layer {} has no elements: no group of {} is named so", T.layers[i].name, geometry.file),
                    "layer names among the geometry's groups: " + listed(groups));
  const int layers = static_cast<int>(T.layers.size());
  for (std::size_t i = 0; i < T.inclusions.size(); ++i)
    if (T.inclusions[i].shape == InclusionSpec::Shape::Mesh)
      describeInclusion(geometry, T.inclusions[i], layers + static_cast<int>(i), T);
  for (auto& I : T.inclusions) {  // placed ones: the layer around the centre gives what they do not
    if (I.shape == InclusionSpec::Shape::Mesh || !(std::isnan(I.friction_coefficient) || std::isnan(I.toughness)))
      continue;
    const LayerSpec& around = T.layers[static_cast<std::size_t>(layerAround(geometry, I, layers))];
    if (std::isnan(I.friction_coefficient)) I.friction_coefficient = around.friction.coefficient;
    if (std::isnan(I.toughness)) I.toughness = around.toughness;
  }
}

void markSupport(ImportedGeometry& geometry, Section& g) {
  const auto& m = *geometry.mesh;
  const auto given = g.optNumber("support_depth");
  const double depth = given.value_or(0.2 * (geometry.hi[0] - geometry.lo[0]));
  if (!given) g.rememberNumber("support_depth", depth);
  geometry.supported.assign(m.nodes(), 0);
  int facets = 0;
  for (const auto& f : mesh::boundaryFacets(m))
    if (f.normal[0] >= 0.5 && f.centroid[0] >= geometry.hi[0] - depth - 1e-12) {
      for (int n : f.nodes) geometry.supported[n] = 1;
      ++facets;
    }
  if (facets == 0)
    throw g.error("support_depth", mm(depth),
                  "holds nothing: no boundary of the geometry faces away from the needle that deep", "a larger depth");
}

void findEntry(ImportedGeometry& geometry, const InsertionSpec& insertion, double maxDepth, Section& ins) {
  const auto frame = needle::InsertionFrame::fromInsertion(insertion);
  const Point from{frame.entry.x(), frame.entry.y(), frame.entry.z()}, dir{frame.axial.x(), frame.axial.y(), frame.axial.z()};
  const auto& m = *geometry.mesh;
  const auto t = mesh::firstCrossing(m, mesh::boundaryFacets(m), from, dir);
  if (!t)
    throw ins.error("entry_offset", mm(insertion.entry_offset),
                    fmt::format("puts the needle path (from {} at {:g} deg to the entry plane) beside the tissue: it "
                                "meets no boundary of {}, which spans x {} to {}, y {} to {}, z {} to {}",
                                mmPoint(from.data()), insertion.entry_angle * 180 / std::numbers::pi, geometry.file,
                                mm(geometry.lo[0]), mm(geometry.hi[0]), mm(geometry.lo[1]), mm(geometry.hi[1]),
                                mm(geometry.lo[2]), mm(geometry.hi[2])),
                    "an entry_offset and entry_angle whose path crosses the geometry (or tissue.geometry.translate)");
  geometry.entry_depth = *t;
  for (int i = 0; i < 3; ++i) geometry.entry_point[i] = from[i] + *t * dir[i];
  if (maxDepth <= *t)
    throw ins.error("profile", mm(maxDepth),
                    fmt::format("never reaches the tissue: the path meets it {} along the needle axis, at {}", mm(*t),
                                mmPoint(geometry.entry_point)),
                    fmt::format("an insertion deeper than {}", mm(*t)));
}

}  // namespace needlesim::scenario
