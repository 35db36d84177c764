// tissue.geometry in realtime3d (engines/realtime3d/tissue.hpp): Gmsh's unstructured tetrahedra of
// a block agree with the generated block of the same element size within that block's own change
// under refinement; what the engine cannot take is refused with its field; the prostate example
// reports its tumour's miss distance.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fmt/format.h>
#include <fstream>
#include <string>

#include "needlesim/core/error.hpp"
#include "needlesim/engines/engine.hpp"
#include "needlesim/engines/memory_sink.hpp"
#include "needlesim/engines/realtime3d/realtime3d_engine.hpp"
#include "needlesim/engines/realtime3d/session.hpp"
#include "needlesim/scenario/reader.hpp"
#include "../support/block_script.hpp"

using namespace needlesim;
using namespace needlesim::realtime3d;

namespace {

std::filesystem::path dir() {
  auto d = std::filesystem::temp_directory_path() / ("needlesim_rt3_imported_" + std::to_string(::getpid()));
  std::filesystem::create_directories(d);
  return d;
}

// A 30 x 20 x 20 mm box (x from the entry plane, y and z centred) of Gmsh tetrahedra of size h mm.
void writeBoxScript(const std::string& name, double h) {
  std::ofstream(dir() / name) << fmt::format(R"(SetFactory("OpenCASCADE");
Box(1) = {{0, -10, -10, 30, 20, 20}};
Physical Volume("gel") = {{1}};
Mesh.MeshSizeMin = {0}; Mesh.MeshSizeMax = {0};
)",
                                             h);
}

std::string scenarioText(const std::string& tissueLine, const std::string& model = "", const std::string& layers = "") {
  return fmt::format(R"(name: imported
tissue:
  {}
{}
needle: {{outer_diameter: 18 G, length: 100 mm, bevel_angle: 30 deg, tip: bevel}}
insertion:
  start_depth: -1 mm
  profile:
    - insert: {{to: 15 mm, speed: 10 mm/s}}
model:
  engine: realtime3d
  time_step: 2 ms
  realtime3d: {{boundary: far-face, refinement: 1, field_interval: 0 s{}}}
output: {{interval: 10 ms}}
)",
                     tissueLine,
                     layers.empty() ? "  material: gelatin_10wt\n  puncture: {force: 0.05 N}\n  cutting: {force: 0.04335 N}\n"
                                      "  friction: {C_p: 3.791 N/m, b_p: 285.053 N s/m^2, static_band: 0.1 mm/s}"
                                    : layers,
                     model);
}

Scenario read(const std::string& yaml) { return scenario::readText(yaml, (dir() / "scenario.yaml").string()); }

struct Outcome {
  double deflection = 0.0, force = 0.0;
};

Outcome insert(const Scenario& sc) {
  const SessionConfig c = engines::realtime3dConfig(sc);
  Session s(c);
  double d = -1e-3;
  while (d < 0.015) s.step(s.poseAtDepth(d += 1e-2 * c.dt), c.dt);
  return {s.last().tip_deflection[0], s.last().axial_force};
}

std::string refusal(const std::string& yaml) {
  try {
    engines::realtime3dConfig(read(yaml));
    engineFor(read(yaml));
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "expected an InputError";
  return "";
}

const std::string kBlock = "block: {length: 30 mm, width: 20 mm, height: 20 mm}";

}  // namespace

// Gmsh's tets of 2.5 mm against the generated block of 2.5 mm (13 x 9 x 9 nodes, uniform, the far
// face held as the geometry's support): the tip deflection and axial force differ by no more than
// the generated block changes when its elements are halved (25 x 17 x 17 nodes).
TEST(Realtime3dImported, GmshTetsAgreeWithTheGeneratedBlockWithinItsRefinementChange) {
  writeBoxScript("box.geo", 2.5);
  const Outcome imported = insert(read(scenarioText("geometry: {file: box.geo, unit: mm}")));
  const Outcome coarse = insert(read(scenarioText(kBlock, ", nodes_depth: 13, nodes_lateral: 9, nodes_height: 9")));
  const Outcome fine = insert(read(scenarioText(kBlock, ", nodes_depth: 25, nodes_lateral: 17, nodes_height: 17")));
  std::printf("imported %.6e %.6e generated %.6e %.6e, refined %.6e %.6e\n", imported.deflection, imported.force,
              coarse.deflection, coarse.force, fine.deflection, fine.force);
  ASSERT_GT(std::abs(coarse.deflection), 1e-4);
  EXPECT_LE(std::abs(imported.deflection - coarse.deflection), std::abs(fine.deflection - coarse.deflection));
  EXPECT_LE(std::abs(imported.force - coarse.force),
            std::max(std::abs(fine.force - coarse.force), 2e-3 * std::abs(coarse.force)));
}

// A 2D mesh, layers the engine would place by depth and markers are refused, naming the field.
TEST(Realtime3dImported, RefusesWhatItCannotTake) {
  std::ofstream(dir() / "square.geo") << test_support::blockScript(0.020, 10, 1.0);
  writeBoxScript("box_coarse.geo", 5.0);
  const std::string box = "geometry: {file: box_coarse.geo, unit: mm}";
  std::string why = refusal(scenarioText("geometry: {file: square.geo, unit: m}"));
  EXPECT_NE(why.find("tissue.geometry"), std::string::npos) << why;
  const std::string twoLayers = R"(  layers:
    - {name: gel, thickness: 10 mm, material: gelatin_10wt, cutting: {force: 0.04 N}, friction: {C_p: 3.8 N/m}}
    - {name: deep, thickness: 20 mm, material: gelatin_10wt, cutting: {force: 0.04 N}, friction: {C_p: 3.8 N/m}})";
  why = refusal(scenarioText(box, "", twoLayers));
  EXPECT_NE(why.find("tissue.layers"), std::string::npos) << why;
  why = refusal(scenarioText(box, ", markers: [{name: m, x: 10 mm, y: 2 mm}]"));
  EXPECT_NE(why.find("model.realtime3d.markers"), std::string::npos) << why;
}

// examples/anatomy/prostate_tumour_realtime3d.yaml: the gland's tets, the tumour its group; the needle
// ends within the gland's size of the displaced tumour centre, which the insertion has pushed deeper.
TEST(Realtime3dImported, ProstateTumourReportsItsMissDistance) {
  const MemorySink sink = runInMemory(scenario::readFile(NEEDLESIM_SOURCE_DIR "/examples/anatomy/prostate_tumour_realtime3d.yaml"));
  ASSERT_TRUE(sink.results.count("tumour_miss_distance"));
  const double miss = sink.results.at("tumour_miss_distance").value, shift = sink.results.at("tumour_shift_axial").value;
  std::printf("miss %.4g mm, axial shift %.4g mm\n", miss * 1e3, shift * 1e3);
  EXPECT_GT(miss, 0.0);
  EXPECT_LT(miss, 0.02);
  EXPECT_GT(shift, 0.0);
}
