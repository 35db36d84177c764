// tissue.geometry in the explicit engine (scenario/tissue_geometry.hpp, explicit_setup.cpp
// cutSeam): the generated 20 x 20 mm block imported as a Gmsh script of the same 0.5 mm grid
// gives the generated block's forces (same nodes and elements: round-off apart); the script in
// millimetres with unit mm gives the metre script's forces; a missing or misfitting unit, a path
// beside the tissue, a group the scenario does not name and an engine that takes no geometry are
// refused with the field; closed surfaces become a body and a target inclusion of their own.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fmt/format.h>
#include <fstream>
#include <numbers>
#include <string>

#include "engine_tables.hpp"
#include "needlesim/core/error.hpp"
#include "needlesim/engines/engine.hpp"
#include "needlesim/engines/memory_sink.hpp"
#include "needlesim/mesh/gmsh_reader.hpp"
#include "needlesim/scenario/reader.hpp"
#include "../support/block_script.hpp"
#include "../support/gmsh_writes.hpp"

using namespace needlesim;

namespace {

std::filesystem::path dir() {
  auto d = std::filesystem::temp_directory_path() / ("needlesim_imported_" + std::to_string(::getpid()));
  std::filesystem::create_directories(d);
  return d;
}

// The generated block's grid (element_size = max_element_size = 0.5 mm) as a Gmsh script, in
// units of `scale` metres.
void writeBlockScript(const std::string& name, double scale) {
  std::ofstream(dir() / name) << test_support::blockScript(0.020, 40, scale);
}

std::string scenarioText(const std::string& tissueLine, const std::string& engine = "explicit") {
  return fmt::format(R"(name: imported
tissue:
  {}
  material: {{law: neo-hookean, C10: 3.6 kPa, nu: 0.45, density: 1000 kg/m^3}}
  friction: {{coefficient: 0.3}}
needle: {{outer_diameter: 2 mm, length: 40 mm, bevel_angle: 45 deg, tip: bevel, youngs_modulus: 200 GPa}}
insertion:
  start_depth: -0.5 mm
  profile:
    - insert: {{to: 5 mm, speed: 10 mm/s}}
model:
  engine: {}
  explicit: {{dimension: 2d, element: quad4, element_size: 0.5 mm, max_element_size: 0.5 mm, core_width: 20 mm,
              mass_scaling: 15, tip_friction: 0}}
output: {{interval: 10 ms}}
)",
                     tissueLine, engine);
}

Scenario read(const std::string& yaml) { return scenario::readText(yaml, (dir() / "scenario.yaml").string()); }

std::string refusal(const std::string& yaml) {
  try {
    engineFor(read(yaml));
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "expected an InputError";
  return "";
}

double largestRelativeDifference(const std::vector<double>& a, const std::vector<double>& b) {
  EXPECT_EQ(a.size(), b.size());
  double largest = 0.0, scale = 0.0;
  for (double v : b) scale = std::max(scale, std::abs(v));
  for (std::size_t i = 0; i < std::min(a.size(), b.size()); ++i) largest = std::max(largest, std::abs(a[i] - b[i]));
  return largest / scale;
}

}  // namespace

TEST(ImportedGeometry, TheGeneratedBlockImportedGivesItsForcesInEveryUnit) {
  writeBlockScript("block_mm.geo", 1e-3);
  writeBlockScript("block_m.geo", 1.0);
  const auto generated = runInMemory(read(scenarioText("block: {length: 20 mm, width: 20 mm, height: 20 mm}")));
  const auto mm = runInMemory(read(scenarioText("geometry: {file: block_mm.geo, unit: mm}")));
  const auto m = runInMemory(read(scenarioText("geometry: {file: block_m.geo, unit: m}")));
  const auto f = explicit_test::column(generated, "forces", "force_total");
  ASSERT_GT(*std::max_element(f.begin(), f.end()), 1e-3);  // the needle cuts and rubs: a force of some mN
  // the same nodes, elements, seam and held face: the same equations, round-off apart
  EXPECT_LT(largestRelativeDifference(explicit_test::column(mm, "forces", "force_total"), f), 1e-6);
  EXPECT_LT(largestRelativeDifference(explicit_test::column(m, "forces", "force_total"), f), 1e-6);
  EXPECT_EQ(explicit_test::column(mm, "seam", "depth").size(), explicit_test::column(generated, "seam", "depth").size());
}

// The cohesive zone (seed 004 eq 14, seed 001) on the seam through an imported quad mesh: the
// generated block's grid as a script gives the generated block's forces and dissipation; a mesh
// whose seam pairs could not all be moved onto the seam plane is refused, naming the file.
std::string withCohesive(std::string yaml) {
  yaml.replace(yaml.find("  friction: {coefficient: 0.3}\n"), 0, "  interaction: {toughness: 2 J/m^2}\n");
  yaml.replace(yaml.find("tip_friction: 0}"), 16, "tip_friction: 0, cohesive: {enable: true, critical_separation: 0.5 mm}}");
  return yaml;
}

TEST(ImportedGeometry, TheCohesiveZoneFollowsTheSeamThroughAnImportedMesh) {
  writeBlockScript("block_mm.geo", 1e-3);
  const auto generated = runInMemory(read(withCohesive(scenarioText("block: {length: 20 mm, width: 20 mm, height: 20 mm}"))));
  const auto imported = runInMemory(read(withCohesive(scenarioText("geometry: {file: block_mm.geo, unit: mm}"))));
  const auto f = explicit_test::column(generated, "forces", "force_total");
  ASSERT_GT(*std::max_element(f.begin(), f.end()), 1e-3);
  EXPECT_LT(largestRelativeDifference(explicit_test::column(imported, "forces", "force_total"), f), 1e-6);
  const double D = generated.results.at("cohesive_dissipation").value;
  EXPECT_GT(D, 0.0);  // the zone opened and dissipated
  EXPECT_NEAR(imported.results.at("cohesive_dissipation").value, D, 1e-6 * D);
  // Gmsh's unstructured quads of an elliptic disc: a seam pair near the curved entry is left
  // beside the plane (moving it would collapse an element)
  std::ofstream(dir() / "disc.geo") << R"(SetFactory("OpenCASCADE");
Disk(1) = {10, 0, 0, 10, 8}; Recombine Surface {1};
Mesh.MeshSizeMax = 0.6; Mesh.MeshSizeMin = 0.6;
Physical Surface("gel") = {1};
)";
  std::string why;
  try {
    runInMemory(read(withCohesive(scenarioText("geometry: {file: disc.geo, unit: mm}"))));
    ADD_FAILURE() << "expected an InputError";
  } catch (const InputError& e) {
    why = e.what();
  }
  EXPECT_NE(why.find("lie beside the seam plane"), std::string::npos) << why;
  EXPECT_NE(why.find("disc.geo"), std::string::npos) << why;
}

TEST(ImportedGeometry, AMissingOrMisfittingUnitIsRefused) {
  writeBlockScript("block_mm.geo", 1e-3);
  std::string why = refusal(scenarioText("geometry: {file: block_mm.geo}"));
  EXPECT_NE(why.find("tissue.geometry.unit"), std::string::npos) << why;
  why = refusal(scenarioText("geometry: {file: block_mm.geo, unit: m}"));
  EXPECT_NE(why.find("20000 mm across"), std::string::npos) << why;
  EXPECT_NE(why.find("with unit: mm it is 20 mm"), std::string::npos) << why;
}

TEST(ImportedGeometry, APathBesideTheTissueOrAnUnnamedGroupIsRefused) {
  writeBlockScript("block_mm.geo", 1e-3);
  std::string yaml = scenarioText("geometry: {file: block_mm.geo, unit: mm}");
  yaml.replace(yaml.find("  start_depth"), 0, "  entry_offset: 15 mm\n");
  std::string why = refusal(yaml);
  EXPECT_NE(why.find("insertion.entry_offset"), std::string::npos) << why;
  EXPECT_NE(why.find("beside the tissue"), std::string::npos) << why;
  yaml = scenarioText(R"(geometry: {file: block_mm.geo, unit: mm}
  layers:
    - {name: skin, material: gelatin_10wt}
    - {name: gell, material: gelatin_10wt})");
  yaml.replace(yaml.find("  material: {law"), yaml.find("needle:") - yaml.find("  material: {law"), "");
  why = refusal(yaml);
  EXPECT_NE(why.find("neither a layer nor an inclusion"), std::string::npos) << why;
  EXPECT_NE(why.find("did you mean gell?"), std::string::npos) << why;
}

TEST(ImportedGeometry, AnEngineThatTakesNoGeometryRefusesIt) {
  writeBlockScript("block_mm.geo", 1e-3);
  const std::string why = refusal(scenarioText("geometry: {file: block_mm.geo, unit: mm}", "lumped"));
  EXPECT_NE(why.find("engine lumped does not take an imported 2D geometry"), std::string::npos) << why;
  EXPECT_NE(why.find("explicit"), std::string::npos) << why;
}

TEST(ImportedGeometry, ClosedSurfacesMakeABodyAndATargetInclusion) {
  // Gmsh writes the two spheres' surfaces; needlesim meshes them into tetrahedra
  test_support::gmshWrites(dir(), "spheres.geo", R"(SetFactory("OpenCASCADE");
Sphere(1) = {10, 0, 0, 10}; Mesh.MeshSizeMax = 1.5; Mesh 2; Save "organ.stl";
Delete All; SetFactory("OpenCASCADE"); Sphere(2) = {10, 1, 0, 3}; Mesh.MeshSizeMax = 0.8; Mesh 2; Save "tumour.stl";
)");
  std::filesystem::current_path(dir());
  const std::string yaml = R"(name: organ
tissue:
  geometry:
    surfaces: [{file: organ.stl}, {file: tumour.stl}]
    unit: mm
    element_size: 2 mm
    translate: {x: 1 mm}
  layers: [{name: organ, material: {law: neo-hookean, C10: 9.5 kPa, nu: 0.45}}]
  inclusions: [{name: tumour, target: true, material: {law: neo-hookean, C10: 16.6 kPa, nu: 0.45}}]
needle: {outer_diameter: 18 G, length: 60 mm, tip: bevel, bevel_angle: 20 deg}
insertion: {profile: [{insert: {to: 12 mm, speed: 10 mm/s}}]}
model: {engine: explicit, explicit: {dimension: 3d, element: tet4}}
)";
  std::ofstream(dir() / "organ.yaml") << yaml;
  const Scenario sc = scenario::readFile(dir() / "organ.yaml");
  ASSERT_TRUE(sc.tissue.geometry);
  const auto& I = sc.tissue.inclusions.at(0);
  EXPECT_EQ(I.shape, InclusionSpec::Shape::Mesh);
  // the tumour's centre (11, 1, 0) mm after the 1 mm shift and its radius, from its tetrahedra
  EXPECT_NEAR(I.x, 11e-3, 0.05e-3);
  EXPECT_NEAR(I.y, 1e-3, 0.05e-3);
  EXPECT_NEAR(I.radius, 3e-3, 0.03 * 3e-3);  // inscribed facets at 0.8 mm: about 1 % short
  // the path meets the organ's apex at x = 1 mm, the far pole at 21 mm: the facets of a 10 mm
  // sphere at 1.5 mm lie up to h^2 / (4 r) = 0.06 mm inside it
  EXPECT_NEAR(sc.tissue.geometry->entry_depth, 1e-3, 0.06e-3);
  EXPECT_NEAR(sc.tissue.length, 21e-3, 0.06e-3);
  std::filesystem::remove_all(dir());
}

TEST(ImportedGeometry, RotateThenTranslatePlacesTheMeshInTheTissueFrame) {
  writeBlockScript("block_mm.geo", 1e-3);  // x in [0, 20], y in [-10, 10] mm
  std::string yaml = scenarioText("geometry: {file: block_mm.geo, unit: mm, rotate: {z: 90 deg}, translate: {x: 10 mm}}");
  yaml.replace(yaml.find("  start_depth"), 0, "  entry_offset: 5 mm\n");
  const Scenario sc = read(yaml);
  // a quarter turn about z takes (x, y) to (-y, x): x in [-10, 10] + 10 mm, y in [0, 20] mm
  EXPECT_NEAR(sc.tissue.geometry->lo[0], 0.0, 1e-12);
  EXPECT_NEAR(sc.tissue.geometry->hi[0], 20e-3, 1e-12);
  EXPECT_NEAR(sc.tissue.geometry->lo[1], 0.0, 1e-12);
  EXPECT_NEAR(sc.tissue.geometry->hi[1], 20e-3, 1e-12);
  EXPECT_NEAR(sc.tissue.width, 40e-3, 1e-12);  // the centred block that holds it
  EXPECT_NEAR(sc.tissue.geometry->entry_depth, 0.0, 1e-12);  // the path at y = 5 mm meets the face x = 0
}
