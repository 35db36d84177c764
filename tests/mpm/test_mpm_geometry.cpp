// The mpm engine with an imported geometry (tissue.geometry): the block's lattice kept inside the
// mesh's tetrahedra, each point with its element's layer or inclusion, and the grid held at the
// geometry's supported side (engines/mpm/geometry_fill.hpp, docs/models/mpm.md).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>

#include "mpm_test_scenario.hpp"
#include "needlesim/core/error.hpp"
#include "needlesim/engines/mpm/mpm_engine.hpp"
#include "needlesim/mesh/volume_mesh.hpp"

using namespace needlesim;
using namespace needlesim::mpm_test;

namespace {

// A Gmsh script in the test's temporary folder; returns its absolute path.
std::string script(const std::string& name, const std::string& text) {
  const auto dir = std::filesystem::temp_directory_path() / "needlesim_mpm_geometry";
  std::filesystem::create_directories(dir);
  const auto path = dir / name;
  std::ofstream(path) << "SetFactory(\"OpenCASCADE\");\n" << text;
  return path.string();
}

// The small block of smallScenario with the default faces (exit fixed, the others free).
std::string blockScenario() {
  return replaced(smallScenario(), "    faces: {exit: fixed, y_min: roller, y_max: roller, z_min: roller, z_max: roller}\n",
                  "");
}

// The same scenario with the block replaced by the geometry of `file` (unit mm).
std::string geometryScenario(const std::string& file, const std::string& inclusions = "") {
  std::string s = replaced(blockScenario(), "  block: {length: 6 mm, width: 4 mm, height: 4 mm}\n",
                           "  geometry: {file: " + file + ", unit: mm}\n");
  if (!inclusions.empty())
    s = replaced(s, "  friction: {coefficient: 0.255}\n", "  friction: {coefficient: 0.255}\n  inclusions:\n" + inclusions);
  return s;
}

// The points mpm makes of a scenario, without running it.
std::unique_ptr<mpm::MpmSolver> points(const Scenario& sc, std::vector<std::vector<std::size_t>>* members = nullptr) {
  const engines::MpmSetup setup = engines::mpmSetup(sc);
  auto solver = std::make_unique<mpm::MpmSolver>(setup.config);
  for (const auto& m : setup.materials) solver->addMaterial(m);
  auto inc = engines::addTissue(*solver, sc, setup);
  if (members) *members = inc;
  return solver;
}

}  // namespace

// A Gmsh box of the block's size, meshed in tetrahedra of 2 mm (coarser than the 0.5 mm points),
// is the block: the same 768 points at the same places, and the supported side (its far face)
// holds the grid nodes that the block's fixed exit face holds wherever a point reaches. So the
// runs agree to round-off: the only differences are in the order of floating-point sums over
// identical inputs (none: the points are pushed in the block's order), hence 1e-9 of the peak.
TEST(MpmGeometry, ImportedBoxIsTheBlock) {
  const std::string box = script("box.geo", "Box(1) = {0, -2, -2, 6, 4, 4};\nPhysical Volume(\"tissue\") = {1};\n"
                                            "Mesh.MeshSizeMax = 2;\n");
  const Scenario block = scenario::readText(blockScenario(), "block.yaml");
  const Scenario geometry = scenario::readText(geometryScenario(box), "geometry.yaml");
  ASSERT_TRUE(geometry.tissue.geometry);
  EXPECT_EQ(geometry.tissue.geometry->mesh->element, "tet4");
  const auto a = points(block), b = points(geometry);
  ASSERT_EQ(a->size(), 768u);
  ASSERT_EQ(b->size(), a->size());
  for (std::size_t p = 0; p < a->size(); ++p) ASSERT_LT((a->position(p) - b->position(p)).norm(), 1e-15) << p;

  const MemorySink ra = runText(blockScenario()), rb = runText(geometryScenario(box));
  const auto fa = ra.tables.at("forces").column("force_total"), fb = rb.tables.at("forces").column("force_total");
  ASSERT_EQ(fa.size(), fb.size());
  double peak = 0;
  for (double f : fa) peak = std::max(peak, std::abs(f));
  EXPECT_GT(peak, 1e-3);  // the needle loads the tissue
  for (std::size_t i = 0; i < fa.size(); ++i) EXPECT_NEAR(fb[i], fa[i], 1e-9 * peak) << i;
}

// A sphere of radius 3 mm filled with 0.5 mm points: their volume is the sphere's to the lattice's
// resolution. Counting lattice points inside a sphere errs by a fraction of the surface layer
// (4 pi r^2 dp / 2 over 4/3 pi r^3 = 1.5 dp / r = 25 % at most, in practice far less as the errors
// cancel round the surface); the inscribed tetrahedral faceting (0.5 mm edges) removes about
// 3 s / r with sagitta s = l^2 / 8 r, 0.3 %. 2 % holds both with room.
TEST(MpmGeometry, SphereVolumeFromItsPoints) {
  const std::string sphere = script("sphere.geo", "Sphere(1) = {3, 0, 0, 3};\nPhysical Volume(\"tissue\") = {1};\n"
                                                  "Mesh.MeshSizeMax = 0.5;\n");
  const Scenario sc = scenario::readText(geometryScenario(sphere), "sphere.yaml");
  const auto s = points(sc);
  double volume = 0;
  for (std::size_t p = 0; p < s->size(); ++p) volume += s->volume0(p);
  const double exact = 4.0 / 3.0 * std::numbers::pi * std::pow(3e-3, 3);
  EXPECT_NEAR(volume / exact, 1.0, 0.02) << s->size() << " points";
}

// A group named like an inclusion gets the points of its elements, with the inclusion's material
// (and body 1 when it slides: the grid contact, which a second body needs); the run reports its shift.
TEST(MpmGeometry, GroupInclusionGetsItsPoints) {
  const std::string lump = script(
      "lump.geo",
      "Box(1) = {0, -2, -2, 6, 4, 4};\nSphere(2) = {4, 0, 0, 1.2};\n"
      "BooleanFragments{ Volume{1}; Delete; }{ Volume{2}; Delete; }\n"
      "inner() = Volume In BoundingBox {2.7, -1.3, -1.3, 5.3, 1.3, 1.3};\nouter() = Volume{:};\nouter() -= inner();\n"
      "Physical Volume(\"tissue\") = {outer()};\nPhysical Volume(\"lump\") = {inner()};\nMesh.MeshSizeMax = 0.6;\n");
  const std::string inc =
      "    - {name: lump, target: true, interface: sliding, interface_friction: 0.1, material: "
      "{law: fung, mu: 50 kPa, gamma: 1.0, nu: 0.45, density: 1000 kg/m^3}}\n";
  const std::string yaml = replaced(geometryScenario(lump, inc), "    threads: 1\n", "    threads: 1\n    contact: grid\n");
  const Scenario sc = scenario::readText(yaml, "lump.yaml");
  std::vector<std::vector<std::size_t>> members;
  const auto s = points(sc, &members);
  ASSERT_EQ(members.size(), 1u);
  const double expected = 4.0 / 3.0 * std::numbers::pi * std::pow(1.2, 3) / 0.125;  // about 58 points
  EXPECT_NEAR(static_cast<double>(members[0].size()), expected, 0.2 * expected);
  for (std::size_t p : members[0]) {
    EXPECT_EQ(s->material(p), 1);
    EXPECT_EQ(s->body(p), 1);
  }
  EXPECT_EQ(s->size(), 768u);  // the box still holds every lattice point

  const MemorySink r = runText(yaml);
  ASSERT_TRUE(r.results.count("lump_shift_axial"));
  EXPECT_GT(r.results.at("lump_shift_axial").value, 0.0);  // pushed ahead of the tip
}

// What mpm cannot take is refused with the field: the box's faces with a geometry.
TEST(MpmGeometry, RefusesFacesWithAGeometry) {
  const std::string box = script("box_faces.geo", "Box(1) = {0, -2, -2, 6, 4, 4};\nMesh.MeshSizeMax = 2;\n");
  const std::string yaml = replaced(geometryScenario(box), "    threads: 1\n",
                                    "    threads: 1\n    faces: {y_min: roller}\n");
  const Scenario sc = scenario::readText(yaml, "faces.yaml");
  try {
    engines::mpmSetup(sc);
    FAIL() << "accepted model.mpm.faces with a geometry";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("model.mpm.faces"), std::string::npos) << e.what();
  }
}
