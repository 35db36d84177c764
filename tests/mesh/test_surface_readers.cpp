// needlesim's own surface readers (mesh/stl_reader, ply_reader, off_reader, surface_formats,
// vtp_reader) and the .msh pre-check (mesh/msh_check): one closed box written in every format
// gives the same triangles; every malformed file (non-finite or absurd coordinates, counts that do
// not match the data, missing sections, degenerate triangles, unknown extensions) is an InputError
// naming the file, where in it, and what is wrong, never a crash or a silent accept.
#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fmt/format.h>
#include <fstream>
#include <functional>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "needlesim/core/error.hpp"
#include "needlesim/mesh/boundary.hpp"
#include "needlesim/mesh/gmsh_reader.hpp"
#include "needlesim/mesh/surface_formats.hpp"
#include "../support/refusal.hpp"

using namespace needlesim;
namespace fs = std::filesystem;

using needlesim::test::refusal;

namespace {

fs::path tempDir() {
  auto dir = fs::temp_directory_path() / ("needlesim_surface_test_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  return dir;
}

fs::path writeFile(const std::string& name, const std::string& bytes) {
  auto p = tempDir() / name;
  std::ofstream(p, std::ios::binary) << bytes;
  return p;
}


// The surface of `bytes` as file `name`, meshed as Gmsh would be given it: refused with a message
// holding every part.
void expectSurfaceRefused(const std::string& name, const std::string& bytes, std::initializer_list<std::string> parts) {
  SCOPED_TRACE(name);
  const auto path = writeFile(name, bytes);
  const std::string why = refusal([&] { mesh::meshSurfaces({{path.string(), "gel"}}, 2.0); });
  for (const auto& p : parts) EXPECT_NE(why.find(p), std::string::npos) << "missing '" << p << "' in: " << why;
}

// The unit cube [0, 10]^3: 8 corners, 12 triangles turning outwards.
const double kCorner[8][3] = {{0, 0, 0}, {10, 0, 0}, {0, 10, 0}, {10, 10, 0}, {0, 0, 10}, {10, 0, 10}, {0, 10, 10}, {10, 10, 10}};
const int kFace[12][3] = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                          {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};

std::string boxStlAscii() {
  std::string s = "solid box\n";
  for (const auto& f : kFace) {
    s += "  facet normal 0 0 0\n    outer loop\n";
    for (int v : f) s += fmt::format("      vertex {} {} {}\n", kCorner[v][0], kCorner[v][1], kCorner[v][2]);
    s += "    endloop\n  endfacet\n";
  }
  return s + "endsolid box\n";
}

template <class T>
void put(std::string& s, T v, bool big = false) {
  char b[sizeof(T)];
  std::memcpy(b, &v, sizeof(T));
  if (big) std::reverse(b, b + sizeof(T));
  s.append(b, sizeof(T));
}

std::string boxStlBinary() {
  std::string s(80, ' ');
  s.replace(0, 17, "HEADER-OF-THE-BOX");
  put<std::uint32_t>(s, 12);
  for (const auto& f : kFace) {
    for (int k = 0; k < 3; ++k) put<float>(s, 0.0f);
    for (int v : f)
      for (int k = 0; k < 3; ++k) put<float>(s, static_cast<float>(kCorner[v][k]));
    put<std::uint16_t>(s, 0);
  }
  return s;
}

std::string plyHeader(const std::string& format, int vertices, const std::string& faces, const std::string& xyzType = "float") {
  return fmt::format("ply\nformat {} 1.0\ncomment a box\nelement vertex {}\nproperty {} x\nproperty {} y\nproperty {} z\n"
                     "element face {}\nproperty list uchar int vertex_indices\nend_header\n",
                     format, vertices, xyzType, xyzType, xyzType, faces);
}

std::string boxPlyAscii() {
  std::string s = plyHeader("ascii", 8, "12");
  for (const auto& c : kCorner) s += fmt::format("{} {} {}\n", c[0], c[1], c[2]);
  for (const auto& f : kFace) s += fmt::format("3 {} {} {}\n", f[0], f[1], f[2]);
  return s;
}

std::string boxPlyBinary(bool big) {
  std::string s = plyHeader(big ? "binary_big_endian" : "binary_little_endian", 8, "12", "double");
  for (const auto& c : kCorner)
    for (double x : c) put<double>(s, x, big);
  for (const auto& f : kFace) {
    put<std::uint8_t>(s, 3);
    for (int v : f) put<std::int32_t>(s, v, big);
  }
  return s;
}

std::string boxOff() {
  std::string s = "OFF\n# a box\n8 12 0\n";
  for (const auto& c : kCorner) s += fmt::format("{} {} {}\n", c[0], c[1], c[2]);
  for (const auto& f : kFace) s += fmt::format("3 {} {} {}\n", f[0], f[1], f[2]);
  return s;
}

std::string boxObj() {
  std::string s = "# a box\n";
  for (const auto& c : kCorner) s += fmt::format("v {} {} {}\n", c[0], c[1], c[2]);
  for (const auto& f : kFace) s += fmt::format("f {} {} {}\n", f[0] + 1, f[1] + 1, f[2] + 1);
  return s;
}

// Each triangle as its corners' coordinates, starting at its smallest corner (orientation kept), sorted.
std::vector<std::array<double, 9>> canonical(const mesh::TriangleSurface& s) {
  std::vector<std::array<double, 9>> out;
  for (int t = 0; t < s.triangles(); ++t) {
    std::array<std::array<double, 3>, 3> c;
    for (int k = 0; k < 3; ++k)
      for (int i = 0; i < 3; ++i) c[k][i] = s.xyz[3 * s.tri[3 * t + k] + i];
    const int first = static_cast<int>(std::min_element(c.begin(), c.end()) - c.begin());
    std::array<double, 9> r;
    for (int k = 0; k < 3; ++k)
      for (int i = 0; i < 3; ++i) r[3 * k + i] = c[(first + k) % 3][i];
    out.push_back(r);
  }
  std::sort(out.begin(), out.end());
  return out;
}

std::string fileBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream all;
  all << in.rdbuf();
  return all.str();
}

std::string vtpData(const std::string& name) { return std::string(NEEDLESIM_SOURCE_DIR) + "/tests/mesh/data/" + name; }

}  // namespace

TEST(SurfaceReaders, OneBoxInEveryFormatGivesTheSameTriangles) {
  const std::vector<std::pair<std::string, std::string>> files = {
      {"box_ascii.stl", boxStlAscii()}, {"box_binary.stl", boxStlBinary()},    {"box_ascii.ply", boxPlyAscii()},
      {"box_le.ply", boxPlyBinary(false)}, {"box_be.ply", boxPlyBinary(true)}, {"box.off", boxOff()},
      {"box.obj", boxObj()}};
  std::vector<std::array<double, 9>> expected;
  for (const auto& f : kFace) {
    mesh::TriangleSurface one;
    for (int v : f) one.xyz.insert(one.xyz.end(), kCorner[v], kCorner[v] + 3);
    one.tri = {0, 1, 2};
    expected.push_back(canonical(one)[0]);
  }
  std::sort(expected.begin(), expected.end());
  for (const auto& [name, bytes] : files) {
    SCOPED_TRACE(name);
    const auto s = mesh::readOwnSurfaceFormat(writeFile(name, bytes).string());
    ASSERT_TRUE(s.has_value());
    EXPECT_EQ(s->xyz.size(), 24u);  // STL's repeated corners merged: 8 vertices
    EXPECT_EQ(canonical(*s), expected);
    EXPECT_EQ(mesh::openEdge(*s), "");
  }
  // and meshed: the cube's volume exactly
  const auto m = mesh::meshSurfaces({{writeFile("box.off", boxOff()).string(), "gel"}}, 4.0);
  double volume = 0.0;
  for (int e = 0; e < m.elements(); ++e) volume += mesh::elementMeasure(m, e);
  EXPECT_NEAR(volume, 1000.0, 1e-9);
  fs::remove_all(tempDir());
}

TEST(SurfaceReaders, OffPolygonsAreSplitIntoFans) {
  // the cube's six faces as quadrilaterals, colours after two of them
  std::string off = "OFF 8 6 12\n";
  for (const auto& c : kCorner) off += fmt::format("{} {} {}\n", c[0], c[1], c[2]);
  off += "4 0 2 3 1 255 0 0\n4 4 5 7 6\n4 0 1 5 4 0 255 0\n4 2 6 7 3\n4 0 4 6 2\n4 1 3 7 5\n";
  const auto s = mesh::readOwnSurfaceFormat(writeFile("quads.off", off).string());
  EXPECT_EQ(s->triangles(), 12);
  EXPECT_EQ(mesh::openEdge(*s), "");
  fs::remove_all(tempDir());
}

TEST(SurfaceReaders, NonFiniteOrAbsurdCoordinatesAreRefusedNamingTheVertex) {
  std::string stl = boxStlAscii();
  stl.replace(stl.find("vertex 10 0 0"), 13, "vertex nan 0 0");
  expectSurfaceRefused("nan.stl", stl, {"nan.stl:", "facet", "x = nan", "finite coordinates"});
  stl = boxStlAscii();
  stl.replace(stl.find("vertex 10 0 0"), 13, "vertex 10 inf 0");
  expectSurfaceRefused("inf.stl", stl, {"inf.stl:", "y = inf"});
  stl = boxStlAscii();
  stl.replace(stl.find("vertex 10 0 0"), 13, "vertex 10 0 1e300");
  expectSurfaceRefused("huge.stl", stl, {"huge.stl:", "z = 1e+300", "at most 1e+09"});
  std::string binary = boxStlBinary();
  const float nan = std::numeric_limits<float>::quiet_NaN();
  std::memcpy(&binary[84 + 50 * 4 + 12 + 12], &nan, 4);  // triangle 5, vertex 2, x
  expectSurfaceRefused("nan_binary.stl", binary, {"nan_binary.stl", "vertex 2 of triangle 5", "x = nan"});
  std::string ply = boxPlyAscii();
  ply.replace(ply.find("\n10 0 0\n"), 8, "\n10 nan 0\n");
  expectSurfaceRefused("nan.ply", ply, {"nan.ply:12:", "vertex 1", "y = nan"});
  std::string off = boxOff();
  off.replace(off.find("\n10 0 0\n"), 8, "\n10 0 -inf\n");
  expectSurfaceRefused("inf.off", off, {"inf.off:5:", "vertex 1", "z = -inf"});
  std::string obj = boxObj();
  obj.replace(obj.find("v 10 0 0"), 8, "v 1e300 0 0");
  expectSurfaceRefused("huge.obj", obj, {"huge.obj:3:", "vertex 2", "x = 1e+300"});
  std::string vtp = fileBytes(vtpData("tet_ascii.vtp"));
  const std::size_t points = vtp.find('>', vtp.find("<DataArray", vtp.find("<Points"))) + 1;
  const std::size_t first = vtp.find_first_not_of(" \n", points);
  vtp.replace(first, vtp.find_first_of(" \n", first) - first, "nan");
  expectSurfaceRefused("nan.vtp", vtp, {"nan.vtp:", "point 0", "x = nan"});
  fs::remove_all(tempDir());
}

TEST(SurfaceReaders, CountsThatDoNotMatchTheDataAreRefusedWithBothNumbers) {
  std::string binary = boxStlBinary();
  binary[80] = 13;  // 13 triangles counted, 12 present
  const auto path = writeFile("count.stl", binary);
  const std::string why = refusal([&] { mesh::meshSurfaces({{path.string(), "gel"}}, 2.0); });
  EXPECT_NE(why.find("counts 13 triangles"), std::string::npos) << why;
  EXPECT_NE(why.find("684 bytes"), std::string::npos) << why;  // 84 + 50 x 12
  EXPECT_NE(why.find("734 bytes"), std::string::npos) << why;  // 84 + 50 x 13
  EXPECT_EQ(why.find("HEADER-OF"), std::string::npos) << why;  // the header's bytes are not echoed
  std::string ply = boxPlyAscii();
  ply.replace(ply.find("element face 12"), 15, "element face 2000000000");
  expectSurfaceRefused("claims.ply", ply, {"claims.ply:8:", "declares 2000000000 face elements", "hold at most"});
  ply = boxPlyAscii();
  ply.replace(ply.find("element face 12"), 15, "element face 13");
  expectSurfaceRefused("short.ply", ply, {"short.ply", "declares 13 face elements", "ends after 12"});
  std::string le = boxPlyBinary(false);
  expectSurfaceRefused("long.ply", le + std::string(9, '\0'), {"long.ply", "beyond the elements its header declares"});
  std::string off = boxOff();
  off.replace(off.find("8 12 0"), 6, "8 13 0");
  expectSurfaceRefused("short.off", off, {"short.off", "declares 13 faces", "ends after 12"});
  off = boxOff();
  off.replace(off.find("8 12 0"), 6, "8 900000000 0");
  expectSurfaceRefused("claims.off", off, {"claims.off:3:", "900000000 faces", "bytes after the counts"});
  // a compressed block whose header says 100 bytes more than its data (the next array follows it)
  std::string zlib = fileBytes(vtpData("tet_appended_zlib.vtp"));
  const std::size_t data = zlib.find('_', zlib.find("<AppendedData")) + 1;
  std::uint32_t size;
  std::memcpy(&size, &zlib[data + 12], 4);
  size += 100;
  std::memcpy(&zlib[data + 12], &size, 4);
  expectSurfaceRefused("blocksize.vtp", zlib, {"blocksize.vtp", "but its header says"});
  fs::remove_all(tempDir());
}

TEST(SurfaceReaders, DegenerateTrianglesAreRefusedNamingThem) {
  std::string stl = boxStlAscii();
  stl += "solid more\n facet normal 0 0 0\n  outer loop\n   vertex 1 1 1\n   vertex 1 1 1\n   vertex 1 1 1\n  endloop\n endfacet\nendsolid\n";
  expectSurfaceRefused("point.stl", stl, {"point.stl:", "facet 13 is degenerate"});
  std::string off = boxOff();
  off.replace(off.find("\n3 0 2 1\n"), 9, "\n3 0 1 1\n");
  expectSurfaceRefused("repeated.off", off, {"repeated.off:12:", "face 0 is degenerate", "vertex 1 twice"});
  std::string obj = boxObj() + "v 20 0 0\nv 30 0 0\nf 2 9 10\n";  // three corners on the x axis
  expectSurfaceRefused("line.obj", obj, {"line.obj:24:", "degenerate", "lie on one line"});
  fs::remove_all(tempDir());
}

TEST(SurfaceReaders, OffIsReadAsOffNeverAsAScript) {
  const auto before = fs::exists(tempDir() / "pwned.msh");
  EXPECT_FALSE(before);
  expectSurfaceRefused("script.off",
                       "Point(1) = {0, 0, 0};\nPoint(2) = {1, 0, 0};\nPoint(3) = {0, 1, 0};\nSave \"" +
                           (tempDir() / "pwned.msh").string() + "\";\n",
                       {"script.off:1:", "not the line OFF"});
  EXPECT_FALSE(fs::exists(tempDir() / "pwned.msh"));
  expectSurfaceRefused("organ.xyz", boxOff(), {"organ.xyz", "not a surface format needlesim reads", ".stl", ".ply", ".off"});
  fs::remove_all(tempDir());
}

namespace {
// A 2D mesh of two triangles in format 2.2 ASCII.
const char* kMsh22 = R"($MeshFormat
2.2 0 8
$EndMeshFormat
$Nodes
4
1 0 0 0
2 10 0 0
3 10 10 0
4 0 10 0
$EndNodes
$Elements
2
1 2 2 1 1 1 2 3
2 2 2 1 1 1 3 4
$EndElements
)";

std::string replacedText(std::string s, const std::string& from, const std::string& to) {
  const auto at = s.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) s.replace(at, from.size(), to);
  return s;
}

// The same two triangles in format 2.2 binary.
std::string msh22Binary(int nodeCount) {
  std::string s = "$MeshFormat\n2.2 1 8\n";
  put<std::int32_t>(s, 1);
  s += "\n$EndMeshFormat\n$Nodes\n" + std::to_string(nodeCount) + "\n";
  const double xy[4][2] = {{0, 0}, {10, 0}, {10, 10}, {0, 10}};
  for (int n = 0; n < 4; ++n) {
    put<std::int32_t>(s, n + 1);
    put<double>(s, xy[n][0]), put<double>(s, xy[n][1]), put<double>(s, 0.0);
  }
  s += "\n$EndNodes\n$Elements\n2\n";
  put<std::int32_t>(s, 2), put<std::int32_t>(s, 2), put<std::int32_t>(s, 2);
  for (int e = 0; e < 2; ++e) {
    put<std::int32_t>(s, e + 1), put<std::int32_t>(s, 1), put<std::int32_t>(s, 1);
    for (int n : {1, 2 + e, 3 + e}) put<std::int32_t>(s, n);
  }
  return s + "\n$EndElements\n";
}

void expectMshRefused(const std::string& name, const std::string& bytes, std::initializer_list<std::string> parts) {
  SCOPED_TRACE(name);
  const auto path = writeFile(name, bytes);
  const std::string why = refusal([&] { mesh::readGmsh(path.string()); });
  for (const auto& p : parts) EXPECT_NE(why.find(p), std::string::npos) << "missing '" << p << "' in: " << why;
}
}  // namespace

TEST(MshCheck, ValidFilesAreRead) {
  for (const auto& [name, bytes] : {std::pair<std::string, std::string>{"ascii.msh", kMsh22}, {"binary.msh", msh22Binary(4)}}) {
    SCOPED_TRACE(name);
    const auto m = mesh::readGmsh(writeFile(name, bytes).string());
    EXPECT_EQ(m.elements(), 2);
    EXPECT_EQ(m.nodes(), 4);
  }
  fs::remove_all(tempDir());
}

TEST(MshCheck, MalformedMeshFilesAreRefusedNamingTheFileAndPlace) {
  expectMshRefused("nan.msh", replacedText(kMsh22, "3 10 10 0", "3 nan 10 0"), {"nan.msh:8:", "node 3 has x = nan"});
  expectMshRefused("inf.msh", replacedText(kMsh22, "3 10 10 0", "3 10 1e300 0"), {"inf.msh:8:", "node 3 has y = 1e+300"});
  const std::string noNodes = replacedText(kMsh22, "$Nodes\n4\n1 0 0 0\n2 10 0 0\n3 10 10 0\n4 0 10 0\n$EndNodes\n", "");
  expectMshRefused("nonodes.msh", noNodes, {"nonodes.msh", "$Elements before $Nodes"});
  expectMshRefused("negative.msh", replacedText(kMsh22, "$Nodes\n4\n", "$Nodes\n-4\n"), {"negative.msh:5:", "declares -4 nodes"});
  expectMshRefused("huge.msh", replacedText(kMsh22, "$Elements\n2\n", "$Elements\n1000000000000\n"),
                   {"huge.msh:12:", "declares 1000000000000 elements", "more than the"});
  expectMshRefused("noend.msh", replacedText(kMsh22, "$EndNodes\n", ""), {"noend.msh", "$EndNodes"});
  expectMshRefused("noformat.msh", std::string(kMsh22).substr(std::string(kMsh22).find("$Nodes")), {"noformat.msh:1:", "$MeshFormat"});
  expectMshRefused("badnode.msh", replacedText(kMsh22, "2 2 2 1 1 1 3 4", "2 2 2 1 1 1 3 9"),
                   {"badnode.msh:14:", "element 2 uses node 9"});
  expectMshRefused("count.msh", msh22Binary(40), {"count.msh", "declares 40 nodes", "more than the"});
  std::string binaryNan = msh22Binary(4);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  std::memcpy(&binaryNan[binaryNan.find("$Nodes\n4\n") + 9 + 2 * 28 + 4 + 8], &nan, 8);  // node 3's y
  expectMshRefused("binarynan.msh", binaryNan, {"binarynan.msh", "node 3 has y = nan", "byte"});
  fs::remove_all(tempDir());
}

TEST(SurfaceReaders, LegacyVtkPointsAndCountsAreCheckedBeforeGmshReadsThem) {
  std::string vtk = "# vtk DataFile Version 4.2\nbox\nASCII\nDATASET POLYDATA\nPOINTS 8 double\n";
  for (const auto& c : kCorner) vtk += fmt::format("{} {} {}\n", c[0], c[1], c[2]);
  vtk += "POLYGONS 12 48\n";
  for (const auto& f : kFace) vtk += fmt::format("3 {} {} {}\n", f[0], f[1], f[2]);
  const auto m = mesh::meshSurfaces({{writeFile("box.vtk", vtk).string(), "gel"}}, 4.0);
  double volume = 0.0;
  for (int e = 0; e < m.elements(); ++e) volume += mesh::elementMeasure(m, e);
  EXPECT_NEAR(volume, 1000.0, 1e-9);
  expectSurfaceRefused("nan.vtk", replacedText(vtk, "\n10 0 0\n", "\n10 nan 0\n"), {"nan.vtk:7:", "point 1", "y = nan"});
  expectSurfaceRefused("count.vtk", replacedText(vtk, "POLYGONS 12 48", "POLYGONS 12 4800000000"),
                       {"count.vtk:14:", "POLYGONS declares 4800000000 cell values"});
  expectSurfaceRefused("points.vtk", replacedText(vtk, "POINTS 8 double", "POINTS 9 double"),
                       {"points.vtk", "not a number"});
  fs::remove_all(tempDir());
}
