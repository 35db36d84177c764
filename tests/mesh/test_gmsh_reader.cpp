// mesh/gmsh_reader (Gmsh's library): .msh files of formats 2 and 4, ASCII and binary, first and
// second order, and .geo scripts read into the neutral mesh with the same elements; closed
// surfaces meshed into tetrahedra whose volume is the enclosed one, a surface inside another a
// body of its own; bad files (missing, mixed types, inverted or degenerate elements, open or
// crossing surfaces) refused naming the file.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fmt/format.h>
#include <functional>
#include <fstream>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "needlesim/core/error.hpp"
#include "needlesim/mesh/boundary.hpp"
#include "needlesim/mesh/gmsh_reader.hpp"
#include "needlesim/mesh/vtp_reader.hpp"
#include "../support/gmsh_writes.hpp"
#include "../support/refusal.hpp"

using namespace needlesim;

using needlesim::test::refusal;

namespace {

std::filesystem::path tempDir() {
  auto dir = std::filesystem::temp_directory_path() / ("needlesim_mesh_test_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  return dir;
}

std::filesystem::path writeTemp(const std::string& name, const std::string& text) {
  auto p = tempDir() / name;
  std::ofstream(p) << text;
  return p;
}

double totalMeasure(const mesh::VolumeMesh& m, int tag = -1) {
  double v = 0.0;
  for (int e = 0; e < m.elements(); ++e)
    if (tag < 0 || m.tag[e] == tag) v += mesh::elementMeasure(m, e);
  return v;
}


// A 20 x 10 block of triangles (group "gel"); Gmsh saves it in every format kSaveBlock names.
const char* kBlockScript = R"(
Point(1) = {0, -5, 0, 2}; Point(2) = {20, -5, 0, 2}; Point(3) = {20, 5, 0, 2}; Point(4) = {0, 5, 0, 2};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1};
Physical Surface("gel", 5) = {1};
)";
const char* kSaveBlock = R"(Include "block.geo";
Mesh 2;
Mesh.MshFileVersion = 2.2; Mesh.Binary = 0; Save "block22.msh";
Mesh.MshFileVersion = 2.2; Mesh.Binary = 1; Save "block22b.msh";
Mesh.MshFileVersion = 4.1; Mesh.Binary = 1; Save "block41b.msh";
Mesh.MshFileVersion = 4.1; Mesh.Binary = 0; Save "block41.msh";
SetOrder 2; Save "block41q.msh";
)";

}  // namespace

TEST(GmshReader, EveryFormatAndOrderGivesTheSameElements) {
  const auto script = writeTemp("block.geo", kBlockScript);
  test_support::gmshWrites(script.parent_path(), "save_block.geo", kSaveBlock);
  const auto fromScript = mesh::readGmsh(script.string());
  EXPECT_EQ(fromScript.dim, 2);
  EXPECT_EQ(fromScript.element, "tri3");
  EXPECT_NEAR(totalMeasure(fromScript), 200.0, 1e-9);  // the block's area, every element positive
  for (const char* f : {"block22.msh", "block22b.msh", "block41b.msh", "block41.msh", "block41q.msh"}) {
    SCOPED_TRACE(f);
    const auto m = mesh::readGmsh((script.parent_path() / f).string());
    EXPECT_EQ(m.element, "tri3");  // second order keeps its corners
    EXPECT_EQ(m.elements(), fromScript.elements());
    EXPECT_NEAR(totalMeasure(m), 200.0, 1e-9);
    EXPECT_EQ(m.tag.front(), 5);
    EXPECT_EQ(m.groupNames.at(5), "gel");
  }
  // a second-order file's mid-side nodes are not element corners: no node is left unused
  const auto quadratic = mesh::readGmsh((script.parent_path() / "block41q.msh").string());
  EXPECT_EQ(quadratic.nodes(), fromScript.nodes());
  std::filesystem::remove_all(script.parent_path());
}

TEST(GmshReader, AScriptIsMeshedAtTheElementSizeAsked) {
  const auto script = writeTemp("coarse.geo", R"(
Point(1) = {0, 0, 0}; Point(2) = {10, 0, 0}; Point(3) = {10, 10, 0}; Point(4) = {0, 10, 0};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1};
)");
  const auto coarse = mesh::readGmsh(script.string(), 2.0), fine = mesh::readGmsh(script.string(), 0.5);
  // triangles of side h: about 2 (10 / h)^2 of them (at h = 2 Gmsh makes 162, more than 50, as it
  // puts extra nodes on the boundary curves); at a quarter of the size at least 4 times as many
  EXPECT_GT(fine.elements(), 4 * coarse.elements());
  EXPECT_NEAR(totalMeasure(fine), 100.0, 1e-9);
  std::filesystem::remove_all(script.parent_path());
}

TEST(GmshReader, BadMeshFilesAreRefusedNamingTheFile) {
  EXPECT_NE(refusal([] { mesh::readGmsh("/nonexistent/needlesim.msh"); }).find("does not exist"), std::string::npos);
  const auto garbage = writeTemp("garbage.msh", "not a mesh\n");
  EXPECT_NE(refusal([&] { mesh::readGmsh(garbage.string()); }).find("garbage.msh"), std::string::npos);
  // two quadrilaterals, the second turning the other way
  const auto inverted = writeTemp("inverted.msh", R"($MeshFormat
4.1 0 8
$EndMeshFormat
$Entities
0 0 1 0
1 0 0 0 2 1 0 1 7 0
$EndEntities
$Nodes
1 6 1 6
2 1 0 6
1
2
3
4
5
6
0 0 0
1 0 0
2 0 0
0 1 0
1 1 0
2 1 0
$EndNodes
$Elements
1 2 1 2
2 1 3 2
1 1 2 5 4
2 2 5 6 3
$EndElements
)");
  std::string why = refusal([&] { mesh::readGmsh(inverted.string()); });
  EXPECT_NE(why.find("element 2 (quad4) is inverted"), std::string::npos) << why;
  EXPECT_NE(why.find("inverted.msh"), std::string::npos) << why;
  const auto degenerate = writeTemp("degenerate.msh", R"($MeshFormat
2.2 0 8
$EndMeshFormat
$Nodes
4
1 0 0 0
2 1 0 0
3 0 1 0
4 2 0 0
$EndNodes
$Elements
2
1 2 2 1 1 1 2 3
2 2 2 1 1 1 2 4
$EndElements
)");
  why = refusal([&] { mesh::readGmsh(degenerate.string()); });
  EXPECT_NE(why.find("element 2 (tri3) is degenerate"), std::string::npos) << why;
  const auto mixed = writeTemp("mixed.msh", R"($MeshFormat
2.2 0 8
$EndMeshFormat
$Nodes
5
1 0 0 0
2 1 0 0
3 1 1 0
4 0 1 0
5 2 0 0
$EndNodes
$Elements
2
1 3 2 1 1 1 2 3 4
2 2 2 1 1 2 5 3
$EndElements
)");
  why = refusal([&] { mesh::readGmsh(mixed.string()); });
  EXPECT_NE(why.find("mixes quad4 and tri3"), std::string::npos) << why;
  std::filesystem::remove_all(garbage.parent_path());
}

namespace {
// ASCII STL of the tetrahedron (0,0,0), (a,0,0), (0,a,0), (0,0,a); without its last face when open.
std::string tetrahedronStl(double a, bool open) {
  const double P[4][3] = {{0, 0, 0}, {a, 0, 0}, {0, a, 0}, {0, 0, a}};
  const int faces[4][3] = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  std::string s = "solid tet\n";
  for (int f = 0; f < (open ? 3 : 4); ++f) {
    s += " facet normal 0 0 0\n  outer loop\n";
    for (int v : faces[f]) s += fmt::format("   vertex {} {} {}\n", P[v][0], P[v][1], P[v][2]);
    s += "  endloop\n endfacet\n";
  }
  return s + "endsolid tet\n";
}

// ASCII STL of two overlapping cubes (edge a, the second shifted by a/2 in x, y and z) written as
// one surface: every edge is shared by two facets (closed), but the facets cross each other.
std::string selfCrossingStl(double a) {
  const int faces[12][3] = {{0, 1, 3}, {0, 3, 2}, {4, 6, 7}, {4, 7, 5}, {0, 4, 5}, {0, 5, 1},
                            {2, 3, 7}, {2, 7, 6}, {0, 2, 6}, {0, 6, 4}, {1, 5, 7}, {1, 7, 3}};
  std::string s = "solid twocubes\n";
  for (double o : {0.0, 0.5 * a})
    for (const auto& f : faces) {
      s += " facet normal 0 0 0\n  outer loop\n";
      for (int v : f) s += fmt::format("   vertex {} {} {}\n", o + a * (v >> 2), o + a * ((v >> 1) & 1), o + a * (v & 1));
      s += "  endloop\n endfacet\n";
    }
  return s + "endsolid twocubes\n";
}

// Sphere surfaces (radius, centre x) written as STL by Gmsh's OpenCASCADE kernel.
void writeSphereStl(const std::string& name, double radius, double cx) {
  test_support::gmshWrites(tempDir(), name + ".geo", fmt::format(R"(SetFactory("OpenCASCADE");
Sphere(1) = {{{}, 0, 0, {}}};
Mesh.MeshSizeMax = {};
Mesh 2;
Save "{}.stl";
)",
                                                                  cx, radius, radius / 6, name));
}
}  // namespace

TEST(GmshSurfaces, AClosedSurfaceIsFilledWithTetrahedraOfItsVolume) {
  const auto stl = writeTemp("tet.stl", tetrahedronStl(10.0, false));
  const auto m = mesh::meshSurfaces({{stl.string(), "gel"}}, 2.0);
  EXPECT_EQ(m.dim, 3);
  EXPECT_EQ(m.element, "tet4");
  EXPECT_GT(m.elements(), 20);
  EXPECT_NEAR(totalMeasure(m), 1000.0 / 6.0, 1e-9);  // flat faces: the volume exactly
  EXPECT_EQ(m.groupNames.at(1), "gel");
  std::filesystem::remove_all(stl.parent_path());
}

TEST(GmshSurfaces, ASurfaceInsideAnotherIsAHoleOfItAndABodyOfItsOwn) {
  writeSphereStl("organ", 10.0, 0.0);
  writeSphereStl("tumour", 3.0, 2.0);
  const auto dir = tempDir();
  const auto m = mesh::meshSurfaces({{(dir / "organ.stl").string(), "organ"}, {(dir / "tumour.stl").string(), "tumour"}}, 1.5);
  const double organ = totalMeasure(m, 1), tumour = totalMeasure(m, 2);
  const double sphere = 4.0 / 3.0 * std::numbers::pi;
  // facets inscribed in the spheres at h = r/6 lose about (h/r)^2 / 4 of the volume: under 1 %
  EXPECT_NEAR(tumour, sphere * 27.0, 0.02 * sphere * 27.0);
  EXPECT_NEAR(organ, sphere * (1000.0 - 27.0), 0.02 * sphere * 1000.0);
  EXPECT_EQ(m.groupNames.at(2), "tumour");
  std::filesystem::remove_all(dir);
}

TEST(GmshSurfaces, OpenOrCrossingSurfacesAreRefused) {
  const auto open = writeTemp("open.stl", tetrahedronStl(10.0, true));
  std::string why = refusal([&] { mesh::meshSurfaces({{open.string(), "gel"}}, 2.0); });
  EXPECT_NE(why.find("open.stl"), std::string::npos) << why;
  EXPECT_NE(why.find("is not a closed surface"), std::string::npos) << why;
  writeSphereStl("a", 5.0, 0.0);
  writeSphereStl("b", 5.0, 6.0);
  const auto dir = tempDir();
  why = refusal([&] { mesh::meshSurfaces({{(dir / "a.stl").string(), "a"}, {(dir / "b.stl").string(), "b"}}, 2.0); });
  EXPECT_NE(why.find("cross neither themselves nor each other"), std::string::npos) << why;
  std::filesystem::remove_all(dir);
}

TEST(GmshSurfaces, ASelfIntersectingSurfaceIsRefused) {
  const auto stl = writeTemp("twocubes.stl", selfCrossingStl(10.0));
  const std::string why = refusal([&] { mesh::meshSurfaces({{stl.string(), "gel"}}, 2.0); });
  EXPECT_NE(why.find("twocubes.stl"), std::string::npos) << why;
  EXPECT_NE(why.find("intersect"), std::string::npos) << why;  // Gmsh's report of where
  EXPECT_NE(why.find("cross neither themselves nor each other"), std::string::npos) << why;
  std::filesystem::remove_all(stl.parent_path());
}

TEST(GmshSurfaces, AnObjSurfaceIsReadAndUnreadableFormatsAreRefused) {
  // the tetrahedron of tetrahedronStl as Wavefront OBJ: a comment, texture/normal indices, a
  // negative index; its volume exactly
  const auto obj = writeTemp("tet.obj", "# a tetrahedron\nv 0 0 0\nv 10 0 0\nv 0 10 0\nv 0 0 10\n"
                                        "f 1/1/1 3/1/1 2/1/1\nf 1//1 2//1 4//1\nf 1 4 3\nf 2 3 -1\n");
  const auto m = mesh::meshSurfaces({{obj.string(), "gel"}}, 2.0);
  EXPECT_NEAR(totalMeasure(m), 1000.0 / 6.0, 1e-9);
  const auto bad = writeTemp("bad.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n");
  std::string why = refusal([&] { mesh::meshSurfaces({{bad.string(), "gel"}}, 2.0); });
  EXPECT_NE(why.find("bad.obj:4"), std::string::npos) << why;  // the line
  EXPECT_NE(why.find("face corner 9 names no vertex"), std::string::npos) << why;
  // legacy VTK 5.1 (meshio 5, VTK 9) aborts Gmsh 4.8's reader: refused before it sees the file
  const auto vtk5 = writeTemp("organ.vtk", "# vtk DataFile Version 5.1\nvtk output\nASCII\nDATASET POLYDATA\n");
  why = refusal([&] { mesh::meshSurfaces({{vtk5.string(), "gel"}}, 2.0); });
  EXPECT_NE(why.find("legacy VTK version 5.1"), std::string::npos) << why;
  EXPECT_NE(why.find("vtk42"), std::string::npos) << why;
  const auto vtu = writeTemp("organ.vtu", "<VTKFile type=\"UnstructuredGrid\"></VTKFile>\n");
  why = refusal([&] { mesh::meshSurfaces({{vtu.string(), "gel"}}, 2.0); });
  EXPECT_NE(why.find("organ.vtu"), std::string::npos) << why;
  EXPECT_NE(why.find("VTK XML"), std::string::npos) << why;
  std::filesystem::remove_all(obj.parent_path());
}

namespace {
std::string vtpData(const std::string& name) { return std::string(NEEDLESIM_SOURCE_DIR) + "/tests/mesh/data/" + name; }

std::string fileText(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream all;
  all << in.rdbuf();
  return all.str();
}

std::filesystem::path writeTempBinary(const std::string& name, const std::string& bytes) {
  auto p = tempDir() / name;
  std::ofstream(p, std::ios::binary) << bytes;
  return p;
}
}  // namespace

TEST(GmshSurfaces, VtpSurfacesInEveryEncodingAreRead) {
  // written by VTK's own writer (tests/mesh/data/make_vtp.py)
  const std::vector<std::string> encodings = {"ascii",           "binary",           "binary_zlib",
                                              "binary_zlib_u64", "appended_raw",     "appended_zlib",
                                              "appended_zlib_u64", "appended_base64", "appended_base64_zlib",
                                              "v10_appended_zlib", "v10_binary"};
  for (const auto& e : encodings) {
    SCOPED_TRACE(e);
    const auto m = mesh::meshSurfaces({{vtpData("tet_" + e + ".vtp"), "gel"}}, 2.0);
    EXPECT_EQ(m.element, "tet4");
    EXPECT_NEAR(totalMeasure(m), 1000.0 / 6.0, 1e-9);  // flat faces: the volume exactly
  }
  const auto ascii = mesh::readVtp(vtpData("sphere_ascii.vtp"));
  EXPECT_EQ(ascii.xyz.size(), 3u * 50u);  // vtkSphereSource, resolution 8: 8 x 6 + 2 poles
  EXPECT_EQ(ascii.triangles(), 96);
  for (const auto& e : encodings) {
    SCOPED_TRACE(e);
    const auto s = mesh::readVtp(vtpData("sphere_" + e + ".vtp"));
    EXPECT_EQ(s.xyz, ascii.xyz);
    EXPECT_EQ(s.tri, ascii.tri);
  }
  const auto sphere = mesh::meshSurfaces({{vtpData("sphere_appended_zlib.vtp"), "gel"}}, 0.3);
  EXPECT_NEAR(totalMeasure(sphere), 4.0 / 3.0 * std::numbers::pi, 0.15 * 4.0 / 3.0 * std::numbers::pi);

  // malformed files: refused naming the file, never a crash
  const std::string zlib = fileText(vtpData("tet_appended_zlib.vtp"));
  const std::size_t data = zlib.find('_', zlib.find("<AppendedData")) + 1;
  const auto refused = [&](const std::string& name, const std::string& bytes, const std::string& expected) {
    SCOPED_TRACE(name);
    const auto path = writeTempBinary(name, bytes);
    const std::string why = refusal([&] { mesh::meshSurfaces({{path.string(), "gel"}}, 2.0); });
    EXPECT_NE(why.find(name), std::string::npos) << why;
    EXPECT_NE(why.find(expected), std::string::npos) << why;
  };
  refused("truncated.vtp", zlib.substr(0, data + (zlib.size() - data) / 2), "truncated");
  std::string wrongSize = zlib;  // the points' compressed size (the 4th UInt32 of their header), 2 short
  wrongSize[data + 12] = static_cast<char>(wrongSize[data + 12] - 2);
  refused("wrongsize.vtp", wrongSize, "does not inflate");
  const std::string text = fileText(vtpData("tet_ascii.vtp"));
  std::string grid = text;
  grid.replace(grid.find("PolyData"), 8, "UnstructuredGrid");
  refused("grid.vtp", grid, "not PolyData");
  std::string big = text;
  big.replace(big.find("LittleEndian"), 12, "BigEndian");
  refused("big.vtp", big, "big-endian");
  std::filesystem::remove_all(tempDir());
}
