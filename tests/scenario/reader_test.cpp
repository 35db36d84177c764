// The scenario reader: SI conversion of a valid file, and one test per class
// of bad input checking that the message names file, line, field and what is allowed.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <string>

#include "needlesim/core/error.hpp"
#include "needlesim/scenario/reader.hpp"
#include "expect_error.hpp"
#include "needlesim/scenario/schema.hpp"

using namespace needlesim;

namespace {

const std::string kBase = R"(name: t
tissue:
  block: {length: 55 mm, width: 120 mm, height: 80 mm}
  material: {law: linear, E: 30.74 kPa, nu: 0.422}
  puncture: {force: 0.1 N}
  cutting: {force: 0.04335 N}
  friction: {C_p: 3.791 N/m, b_p: 285.053 N s/m^2}
needle:
  outer_diameter: 18 G
  length: 150 mm
insertion:
  profile:
    - insert: {to: 60 mm, speed: 3 mm/s}
)";

using needlesim::test::expectError;
using needlesim::test::replaced;

}  // namespace

TEST(ScenarioReader, ConvertsEverythingToSI) {
  Scenario s = scenario::readText(kBase, "case.yaml");
  ASSERT_EQ(s.tissue.layers.size(), 1u);
  EXPECT_DOUBLE_EQ(s.tissue.length, 0.055);
  EXPECT_DOUBLE_EQ(s.tissue.layers[0].thickness, 0.055);
  EXPECT_DOUBLE_EQ(s.tissue.layers[0].material.param("E"), 30740.0);
  EXPECT_DOUBLE_EQ(s.tissue.layers[0].friction.b_p, 285.053);
  // Defaults: C_n = C_p, D_p = C_p + b_p dv/2 (continuity of eq 3.23), dv = 0.1 mm/s.
  EXPECT_DOUBLE_EQ(s.tissue.layers[0].friction.C_n, 3.791);
  EXPECT_DOUBLE_EQ(s.tissue.layers[0].friction.static_band, 1e-4);
  EXPECT_NEAR(s.tissue.layers[0].friction.D_p, 3.791 + 285.053 * 0.5e-4, 1e-12);
  EXPECT_NEAR(s.needle.outer_diameter, 1.27e-3, 1e-12);
  EXPECT_NEAR(s.needle.inner_diameter, 0.838e-3, 1e-12);
  EXPECT_NEAR(s.needle.bevel_angle, 20 * std::numbers::pi / 180, 1e-12);
  EXPECT_NEAR(s.insertion.entry_angle, std::numbers::pi / 2, 1e-12);
  ASSERT_EQ(s.insertion.segments.size(), 1u);
  EXPECT_DOUBLE_EQ(s.insertion.segments[0].speed, 3e-3);
  EXPECT_EQ(s.model.engine, "lumped");
  EXPECT_NEAR(s.totalDuration(), 20.0, 1e-12);
}

TEST(ScenarioReader, BuiltInDefaultIsTheGelatinExample) {
  Scenario s = scenario::defaultScenario();
  EXPECT_EQ(s.name, "gelatin_18G_3mms");
  EXPECT_DOUBLE_EQ(s.tissue.layers[0].cutting_force, 0.04335);
  EXPECT_EQ(s.insertion.segments.size(), 3u);
}

TEST(ScenarioReader, ReadsEveryShippedExample) {
  for (const char* f : {"gelatin_18G_3mms.yaml", "layered_skin_fat_muscle.yaml"}) {
    Scenario s = scenario::readFile(std::string(NEEDLESIM_SOURCE_DIR) + "/examples/" + f);
    EXPECT_FALSE(s.tissue.layers.empty()) << f;
  }
  Scenario layered = scenario::readFile(std::string(NEEDLESIM_SOURCE_DIR) + "/examples/layered_skin_fat_muscle.yaml");
  EXPECT_EQ(layered.tissue.layers.size(), 4u);
  EXPECT_EQ(layered.tissue.layers[3].material.law, "fung");
}

TEST(ScenarioReaderErrors, UnknownKeyNamesLineColumnAndAllowedKeys) {
  std::string msg = expectError(replaced(kBase, "  length: 150 mm", "  lenght: 150 mm"),
                                {"case.yaml:10:3", "needle.lenght", "not a known field", "length"});
}

TEST(ScenarioReaderErrors, MissingRequiredKey) {
  expectError(replaced(kBase, "  length: 150 mm\n", ""), {"case.yaml:9", "needle.length", "required"});
  expectError(replaced(kBase, "needle:", "needles:"), {"case.yaml", "needles", "not a known field"});
}

TEST(ScenarioReaderErrors, NegativeModulus) {
  expectError(replaced(kBase, "E: 30.74 kPa", "E: -30.74 kPa"),
              {"case.yaml:4", "tissue.material.E", "-30.74 kPa", "out of range", "> 0 Pa"});
}

TEST(ScenarioReaderErrors, PoissonRatioAtOneHalf) {
  expectError(replaced(kBase, "nu: 0.422", "nu: 0.5"), {"case.yaml:4", "tissue.material.nu", "0.5", "(-1, 0.5)"});
}

TEST(ScenarioReaderErrors, ZeroSpeedForAMovingSegment) {
  expectError(replaced(kBase, "speed: 3 mm/s", "speed: 0 mm/s"),
              {"case.yaml:13", "insertion.profile[0].insert.speed", "out of range", "> 0 m/s"});
}

TEST(ScenarioReaderErrors, MissingUnit) {
  expectError(replaced(kBase, "E: 30.74 kPa", "E: 30.74"), {"case.yaml:4", "tissue.material.E", "has no unit", "kPa"});
}

TEST(ScenarioReaderErrors, WrongUnit) {
  expectError(replaced(kBase, "speed: 3 mm/s", "speed: 3 mm"),
              {"case.yaml:13", "insert.speed", "wrong unit", "mm/s"});
  expectError(replaced(kBase, "nu: 0.422", "nu: 0.422 kPa"), {"tissue.material.nu", "without a unit"});
  expectError(replaced(kBase, "E: 30.74 kPa", "E: 30.74 parsecs"), {"tissue.material.E", "unknown unit 'parsecs'"});
}

TEST(ScenarioReaderErrors, InvalidYamlNamesTheLine) {
  expectError(replaced(kBase, "  length: 150 mm", "  length: [150 mm"), {"case.yaml:", "not valid YAML"});
}

TEST(ScenarioReaderErrors, ProfileInconsistencies) {
  std::string y = replaced(kBase, "    - insert: {to: 60 mm, speed: 3 mm/s}\n",
                           "    - insert: {to: 60 mm, speed: 3 mm/s}\n    - insert: {to: 40 mm, speed: 3 mm/s}\n");
  expectError(y, {"case.yaml:14", "insertion.profile[1].insert.to", "deeper"});
  expectError(replaced(kBase, "to: 60 mm", "to: 200 mm"), {"insert.to", "needle.length"});
  expectError(replaced(kBase, "- insert: {to: 60 mm, speed: 3 mm/s}", "- jump: {to: 60 mm}"),
              {"case.yaml:13", "profile[0].jump", "insert"});
  expectError(replaced(kBase, "- insert: {to: 60 mm, speed: 3 mm/s}", "- pause: {duration: 0 s}"),
              {"pause.duration", "out of range"});
}

TEST(ScenarioReaderErrors, LayersMustFillTheBlock) {
  std::string y = R"(tissue:
  block: {length: 55 mm, width: 120 mm, height: 80 mm}
  layers:
    - {name: skin, thickness: 2 mm, material: gelatin_10wt}
    - {name: fat, thickness: 10 mm, material: gelatin_10wt}
needle: {outer_diameter: 1.27 mm, length: 150 mm}
insertion:
  profile: [{insert: {to: 30 mm, speed: 3 mm/s}}]
)";
  expectError(y, {"case.yaml:4", "tissue.layers", "12 mm", "55 mm"});
}

TEST(ScenarioReaderErrors, MaterialProblems) {
  expectError(replaced(kBase, "material: {law: linear, E: 30.74 kPa, nu: 0.422}", "material: jelly"),
              {"tissue.material", "jelly", "gelatin_10wt"});
  expectError(replaced(kBase, "{law: linear, E: 30.74 kPa, nu: 0.422}", "{law: neo-hookean, E: 30.74 kPa}"),
              {"tissue.material.E", "not a parameter of law 'neo-hookean'", "C10"});
  expectError(replaced(kBase, "{law: linear, E: 30.74 kPa, nu: 0.422}", "{law: neo-hookian, C10: 3 kPa}"),
              {"tissue.material.law", "neo-hookian", "neo-hookean"});
  expectError(replaced(kBase, "{law: linear, E: 30.74 kPa, nu: 0.422}",
                       "{law: neo-hookean, C10: 3 kPa, prony: [{g: 0.6, tau: 1 s}, {g: 0.5, tau: 10 s}]}"),
              {"tissue.material.prony", "sum to less than 1"});
}

TEST(ScenarioReaderErrors, NeedleProblems) {
  expectError(replaced(kBase, "outer_diameter: 18 G", "outer_diameter: 99 G"), {"needle.outer_diameter", "gauge"});
  expectError(replaced(kBase, "outer_diameter: 18 G", "outer_diameter: 18 G\n  inner_diameter: 2 mm"),
              {"needle.inner_diameter", "smaller than the outer diameter"});
  expectError(replaced(kBase, "outer_diameter: 18 G", "outer_diameter: 1.27"), {"needle.outer_diameter", "no unit"});
}

TEST(ScenarioReaderErrors, EmptyAndMissingFiles) {
  expectError("", {"case.yaml", "empty"});
  expectError("just text", {"case.yaml", "section"});
  try {
    scenario::readFile("/nonexistent/x.yaml");
    ADD_FAILURE();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/x.yaml"), std::string::npos);
  }
}

TEST(Schema, EveryFieldHasHelpAndEveryChildSectionExists) {
  auto types = scenario::sectionTypes();
  for (const auto& f : scenario::schema()) {
    EXPECT_FALSE(f.help.empty()) << f.section << "." << f.key;
    if (!f.child.empty())
      EXPECT_NE(std::find(types.begin(), types.end(), f.child), types.end()) << f.section << "." << f.key;
  }
  std::string md = scenario::schemaMarkdown();
  EXPECT_NE(md.find("| `static_band` | mm/s, m/s |"), std::string::npos);
}

TEST(Schema, DocsReferenceIsUpToDate) {
  std::ifstream in(std::string(NEEDLESIM_SOURCE_DIR) + "/docs/scenario-format.md");
  std::string doc((std::istreambuf_iterator<char>(in)), {});
  EXPECT_NE(doc.find(scenario::schemaMarkdown()), std::string::npos)
      << "docs/scenario-format.md is out of date: regenerate its Reference part with "
         "`needlesim schema --markdown`";
}

TEST(ScenarioReader, ReadsInclusionsInTheTissueFrame) {
  const std::string y = replaced(kBase, "  friction: {C_p: 3.791 N/m, b_p: 285.053 N s/m^2}\n",
                                 "  friction: {C_p: 3.791 N/m, b_p: 285.053 N s/m^2, coefficient: 0.2}\n"
                                 "  inclusions:\n"
                                 "    - {name: tumour, depth: 30 mm, lateral: -5 mm, elevation: 2 mm, radius: 6 mm,\n"
                                 "       material: {law: linear, E: 90 kPa, nu: 0.45}, target: true}\n"
                                 "    - {shape: cylinder, depth: 20 mm, lateral: 20 mm, radius: 2 mm, interface: sliding,\n"
                                 "       interface_friction: 0.1, material: {law: linear, E: 10 kPa, nu: 0.45}}\n");
  Scenario s = scenario::readText(y, "case.yaml");
  ASSERT_EQ(s.tissue.inclusions.size(), 2u);
  const auto& t = s.tissue.inclusions[0];
  EXPECT_EQ(t.name, "tumour");
  EXPECT_DOUBLE_EQ(t.x, 0.03);
  EXPECT_DOUBLE_EQ(t.y, -0.005);
  EXPECT_DOUBLE_EQ(t.z, 0.002);
  EXPECT_DOUBLE_EQ(t.radius, 0.006);
  EXPECT_TRUE(t.target);
  EXPECT_FALSE(t.sliding);
  EXPECT_DOUBLE_EQ(t.friction_coefficient, 0.2);  // the surrounding layer's
  EXPECT_DOUBLE_EQ(t.material.param("E"), 90e3);
  const auto& v = s.tissue.inclusions[1];
  EXPECT_EQ(v.name, "inclusion2");
  EXPECT_EQ(v.shape, InclusionSpec::Shape::Cylinder);
  EXPECT_TRUE(v.sliding);
  EXPECT_DOUBLE_EQ(v.interface_friction, 0.1);
}

TEST(ScenarioReader, RefusesAnInclusionOutsideTheBlock) {
  expectError(replaced(kBase, "  cutting:", "  inclusions:\n    - {depth: 50 mm, radius: 10 mm, material: {law: linear, E: 90 kPa, nu: 0.45}}\n  cutting:"),
              {"case.yaml:", "tissue.inclusions[0].radius", "outside the 55 x 120 x 80 mm block"});
  expectError(replaced(kBase, "  cutting:", "  inclusions:\n    - {depth: 20 mm, radius: 1 mm, interface_friction: 0.2, material: {law: linear, E: 90 kPa, nu: 0.45}}\n  cutting:"),
              {"interface_friction", "sliding inclusion only"});
}

// The scenario as understood (Scenario::understood) is a scenario in the input's
// own schema: reading it again understands every shipped example the same way.
TEST(ScenarioReader, TheScenarioAsUnderstoodReadsBackToItself) {
  int n = 0;
  for (const auto& e : std::filesystem::recursive_directory_iterator(std::string(NEEDLESIM_SOURCE_DIR) + "/examples")) {
    if (e.path().extension() != ".yaml" || e.path().parent_path().filename() == "studies") continue;
    const Scenario first = scenario::readFile(e.path());
    ASSERT_FALSE(first.understood.empty()) << e.path();
    const Scenario again = scenario::readText(first.understood, e.path().string() + " (as understood)");
    EXPECT_EQ(first.understood, again.understood) << e.path();
    EXPECT_EQ(first.tissue.layers.size(), again.tissue.layers.size());
    EXPECT_EQ(first.totalDuration(), again.totalDuration()) << e.path();
    ++n;
  }
  EXPECT_GT(n, 15);
}

TEST(ScenarioReader, EveryQuantityUnitReadsBack) {
  // The record writes quantities as "<SI value> <siName>": every unit of the schema must parse.
  for (const auto& f : scenario::schema())
    if (f.kind == scenario::Kind::Quantity) {
      const auto q = units::parse("0.1 " + units::siName(f.dim));
      EXPECT_TRUE(q.dim == f.dim) << f.section << "." << f.key << ": " << units::siName(f.dim);
      EXPECT_DOUBLE_EQ(q.value, 0.1) << f.section << "." << f.key;
    }
}

// The engine a file names, read before the scenario as a whole (the run command's OpenMP choice).
TEST(ScenarioReader, TheEngineNamedIsReadFromTheYamlAlone) {
  const auto dir = std::filesystem::temp_directory_path() / ("needlesim_engine_named_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const auto write = [&](const std::string& name, const std::string& text) {
    std::ofstream(dir / name) << text;
    return dir / name;
  };
  EXPECT_EQ(scenario::engineNamedIn(write("mpm.yaml", kBase + "model: {engine: mpm}\n")), "mpm");
  EXPECT_EQ(scenario::engineNamedIn(write("none.yaml", kBase)), "lumped");
  // a mesh it names is not read: a missing one does not matter here
  EXPECT_EQ(scenario::engineNamedIn(write("mesh.yaml", "tissue:\n  geometry: {file: missing.msh, unit: mm}\n"
                                                       "model: {engine: explicit}\n")),
            "explicit");
  EXPECT_EQ(scenario::engineNamedIn(write("summary.json", R"({"scenario": {"model": {"engine": "explicit"}}, "results": {}})")),
            "explicit");
  EXPECT_EQ(scenario::engineNamedIn(write("list.yaml", kBase + "model: {engine: [mpm]}\n")), "");
  EXPECT_EQ(scenario::engineNamedIn(write("broken.yaml", "model: {engine: mpm\n")), "");
  EXPECT_EQ(scenario::engineNamedIn(dir / "absent.yaml"), "");
  std::filesystem::remove_all(dir);
}
