// mesh/gmsh_reader: a Gmsh 4.1 ASCII file of two quads (entity 1 in physical group 7) and a
// line element (skipped), read into the neutral mesh; bad files are refused naming the file.
// The scenario layer reads model.explicit.mesh relative to the scenario file.
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "needlesim/core/error.hpp"
#include "needlesim/mesh/gmsh_reader.hpp"
#include "needlesim/scenario/mesh_file.hpp"

using namespace needlesim;

namespace {
const char* kTwoQuads = R"($MeshFormat
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
2 3 1 3
1 1 1 1
3 1 2
2 1 3 2
1 1 2 5 4
2 2 5 6 3
$EndElements
)";

std::filesystem::path writeTemp(const std::string& name, const std::string& text) {
  auto dir = std::filesystem::temp_directory_path() / ("needlesim_mesh_test_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  auto p = dir / name;
  std::ofstream(p) << text;
  return p;
}
}  // namespace

TEST(GmshReader, ReadsGmsh41AsciiTopDimensionWithPhysicalTags) {
  const auto path = writeTemp("two_quads.msh", kTwoQuads);
  const mesh::VolumeMesh m = mesh::readGmsh(path.string());
  EXPECT_EQ(m.dim, 2);
  EXPECT_EQ(m.element, "quad4");
  EXPECT_EQ(m.nodesPerElement(), 4);
  EXPECT_EQ(m.elements(), 2);
  EXPECT_EQ(m.nodes(), 6);
  EXPECT_DOUBLE_EQ(m.X[5 * 2 + 0], 2.0);
  EXPECT_EQ(m.conn, (std::vector<int>{0, 1, 4, 3, 1, 4, 5, 2}));  // file order (the second is clockwise)
  EXPECT_EQ(m.tag, (std::vector<int>{7, 7}));
  std::filesystem::remove_all(path.parent_path());
}

TEST(GmshReader, BadFilesAreRefusedNamingTheFile) {
  EXPECT_THROW(mesh::readGmsh("/nonexistent/needlesim.msh"), InputError);
  const auto path = writeTemp("old.msh", "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n");
  try {
    mesh::readGmsh(path.string());
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("old.msh"), std::string::npos) << e.what();
  }
  std::filesystem::remove_all(path.parent_path());
}

TEST(GmshReader, ScenarioMeshPathIsRelativeToTheScenarioFile) {
  const auto path = writeTemp("two_quads.msh", kTwoQuads);
  const auto scenarioFile = (path.parent_path() / "scenario.yaml").string();
  const auto m = scenario::readMeshFile("two_quads.msh", scenarioFile);
  ASSERT_TRUE(m);
  EXPECT_EQ(m->elements(), 2);
  EXPECT_FALSE(scenario::readMeshFile("", scenarioFile));
  std::filesystem::remove_all(path.parent_path());
}
