// Input the scenario reader refuses up front (so that `check` and `run` agree): duplicate keys,
// a second document, unknown tags, text that is not UTF-8, counts with a fraction, sizes and
// entry points that cannot be meant, numbers out of a double's range, units of the wrong kind,
// and oversized files. Each test asserts the line and the words the user needs.
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <string>

#include "needlesim/core/error.hpp"
#include "needlesim/core/units.hpp"
#include "needlesim/scenario/reader.hpp"
#include "expect_error.hpp"
#include "needlesim/study/study.hpp"

using namespace needlesim;

namespace {

// Line numbers below refer to this text (line 1 is "name: t").
const std::string kBase = R"(name: t
tissue:
  block: {length: 55 mm, width: 120 mm, height: 80 mm}
  material: {law: linear, E: 30.74 kPa, nu: 0.422}
  puncture: {force: 0.1 N}
  cutting: {force: 0.04335 N}
  friction:
    C_p: 3.791 N/m
    b_p: 285.053 N s/m^2
needle:
  outer_diameter: 18 G
  length: 150 mm
insertion:
  profile:
    - insert: {to: 60 mm, speed: 3 mm/s}
)";

using needlesim::test::expectError;
using needlesim::test::replaced;

std::filesystem::path tempFile(const std::string& name) {
  return std::filesystem::temp_directory_path() / ("needlesim_bad_input_" + name);
}

}  // namespace

TEST(ScenarioBadInput, BaseIsValid) { EXPECT_NO_THROW(scenario::readText(kBase, "case.yaml")); }

TEST(ScenarioBadInput, DuplicateKeyNamesBothLines) {
  expectError(replaced(kBase, "    b_p: 285.053 N s/m^2\n", "    b_p: 285.053 N s/m^2\n    C_p: 9 N/m\n"),
              {"case.yaml:10:", "tissue.friction.C_p", "key 'C_p' given twice (lines 8 and 10)"});
}

TEST(ScenarioBadInput, DuplicateSectionNamesBothLines) {
  expectError(kBase + "needle: {outer_diameter: 20 G, length: 100 mm}\n",
              {"case.yaml:16:", "key 'needle' given twice (lines 10 and 16)"});
  expectError(kBase + "model: {engine: lumped}\nmodel: {engine: mpm}\n", {"key 'model' given twice (lines 16 and 17)"});
}

TEST(ScenarioBadInput, DuplicateKeyInAFlowMapping) {
  expectError(replaced(kBase, "{force: 0.1 N}", "{force: 0.1 N, force: 0.2 N}"),
              {"case.yaml:5:", "tissue.puncture.force", "given twice (lines 5 and 5)"});
}

TEST(ScenarioBadInput, SameKeyInDifferentSectionsIsFine) {
  // 'force' appears in puncture and cutting, 'length' in block and needle.
  EXPECT_NO_THROW(scenario::readText(kBase, "case.yaml"));
}

TEST(ScenarioBadInput, SecondDocumentIsRefusedWithItsLine) {
  expectError(kBase + "---\nname: other\n", {"case.yaml:16:", "second YAML document", "'---'"});
}

TEST(ScenarioBadInput, UnknownTagIsRefusedWithTagAndLine) {
  expectError(replaced(kBase, "outer_diameter: 18 G", "outer_diameter: !gauge 18 G"),
              {"case.yaml:11:", "needle.outer_diameter", "unknown tag", "'!gauge'"});
  // YAML's own tags are fine.
  EXPECT_NO_THROW(scenario::readText(replaced(kBase, "length: 150 mm", "length: !!str 150 mm"), "case.yaml"));
}

TEST(ScenarioBadInput, Latin1TextIsRefusedWithLineAndByte) {
  const std::string msg = expectError(replaced(kBase, "name: t\n", "name: t\ndescription: caf\xE9\n"),
                                      {"case.yaml:2:17", "not UTF-8", "byte 17 of line 2", "0xE9", "save it as UTF-8"});
  EXPECT_EQ(msg.find('\xE9'), std::string::npos) << "the raw byte is echoed: " << msg;
  // UTF-8 text (and a byte-order mark) is fine.
  EXPECT_NO_THROW(scenario::readText("\xEF\xBB\xBF" + replaced(kBase, "name: t\n", "name: t\ndescription: caf\xC3\xA9\n"),
                                     "case.yaml"));
}

TEST(ScenarioBadInput, CountWithAFractionIsRefused) {
  expectError(kBase + "model:\n  engine: realtime2d\n  realtime2d: {nodes_depth: 2.5}\n",
              {"case.yaml:18:", "model.realtime2d.nodes_depth", "must be a whole number", "'2.5'", "[2, 2000]"});
  expectError(kBase + "model:\n  realtime2d: {nodes_lateral: 1}\n", {"nodes_lateral", "out of range", "[3, 2000]"});
  expectError(kBase + "model:\n  mpm: {threads: 1.5}\n", {"model.mpm.threads", "must be a whole number"});
  expectError(kBase + "model:\n  steering: {snapshots: 2.5}\n", {"model.steering.snapshots", "whole number"});
}

TEST(ScenarioBadInput, NewmarkGammaBelowOneHalfIsRefusedAsRunWould) {
  expectError(kBase + "model:\n  realtime2d: {newmark_gamma: 0}\n",
              {"case.yaml:17:", "model.realtime2d.newmark_gamma", "out of range", "[0.5, 1]"});
  EXPECT_NO_THROW(scenario::readText(kBase + "model:\n  realtime2d: {newmark_gamma: 0.5}\n", "case.yaml"));
}

TEST(ScenarioBadInput, Realtime2dEntryAngleBelow45DegIsRefusedAsRunWould) {
  const std::string angled = replaced(kBase, "insertion:\n", "insertion:\n  entry_angle: 30 deg\n");
  expectError(angled + "model: {engine: realtime2d}\n",
              {"case.yaml:14:", "insertion.entry_angle", "'30 deg'", "45 deg to 90 deg for engine realtime2d"});
  EXPECT_NO_THROW(scenario::readText(angled, "case.yaml"));  // the lumped engine takes any angle
}

TEST(ScenarioBadInput, EntryPointOutsideTheEntryFaceIsRefusedInTheUsersUnit) {
  expectError(replaced(kBase, "insertion:\n", "insertion:\n  entry_offset: 1 m\n"),
              {"case.yaml:14:", "insertion.entry_offset", "outside the entry face", "'1 m'", "-0.06 m to 0.06 m",
               "-0.06 m < entry_offset < 0.06 m"});
  expectError(replaced(kBase, "insertion:\n", "insertion:\n  entry_offset: -60 mm\n"),
              {"entry_offset", "-60 mm to 60 mm"});
  EXPECT_NO_THROW(scenario::readText(replaced(kBase, "insertion:\n", "insertion:\n  entry_offset: 59 mm\n"), "case.yaml"));
}

TEST(ScenarioBadInput, ImplausibleSizesAreRefused) {
  expectError(replaced(kBase, "length: 55 mm", "length: 55 Mm"),
              {"case.yaml:3:", "tissue.block.length", "out of range", "'55 Mm'", "(0, 1] m"});
  expectError(replaced(kBase, "  length: 150 mm", "  length: 150 m"), {"case.yaml:12:", "needle.length", "(0, 1] m"});
  expectError(replaced(kBase, "18 G", "5 cm"), {"case.yaml:11:", "needle.outer_diameter", "(0, 0.02] m"});
}

TEST(ScenarioBadInput, NumberOutOfRangeOfADoubleSaysSo) {
  expectError(replaced(kBase, "length: 55 mm", "length: 1e400 mm"),
              {"case.yaml:3:", "tissue.block.length", "out of range of a double", "'1e400 mm'"});
  EXPECT_THROW(units::parse("1e-400 mm"), std::invalid_argument);
  EXPECT_THROW(units::parse("1 m^99999999999"), std::invalid_argument);  // not std::out_of_range
}

TEST(ScenarioBadInput, FractionForALengthNamesTheUnitAndWhatIsNeeded) {
  const std::string msg = expectError(replaced(kBase, "length: 55 mm", "length: 55 %"),
                                      {"case.yaml:3:", "tissue.block.length", "unit '%'", "fraction", "m, mm, um, cm"});
  EXPECT_EQ(msg.find("has no unit"), std::string::npos) << msg;
}

TEST(ScenarioBadInput, EchoedValuesAreTruncatedAndEscaped) {
  const std::string huge(10'000'000, 'x');
  std::string msg = expectError(replaced(kBase, "name: t", "name: \"a\\e[31m" + huge + "\""),
                                {"case.yaml:1:", "name", "a\\x1b[31m", "... (10000006 bytes)"});
  EXPECT_LT(msg.size(), 600u);
  EXPECT_EQ(msg.find('\x1b'), std::string::npos);
  // A long unknown unit is cut as well.
  msg = expectError(replaced(kBase, "length: 55 mm", "length: 55 " + std::string(5000, 'q')), {"unknown unit"});
  EXPECT_LT(msg.size(), 600u);
}

TEST(ScenarioBadInput, OversizedFileIsRefusedBeforeParsing) {
  const auto path = tempFile("huge.yaml");
  {
    std::ofstream out(path);
    out << kBase << "extra:\n";
    const std::string line = "  unknown_key_0000000: value\n";
    for (std::size_t n = 0; n < (17u << 20); n += line.size()) out << line;
  }
  const auto t0 = std::chrono::steady_clock::now();
  try {
    scenario::readFile(path);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("larger than the 16.0 MB"), std::string::npos) << msg;
    EXPECT_NE(msg.find(path.string()), std::string::npos) << msg;
  }
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 1.0);
  std::filesystem::remove(path);
}

// A device or a pipe that never ends (here /dev/zero) is read only up to the size limit, then refused.
TEST(ScenarioBadInput, EndlessDeviceIsRefusedBySize) {
  if (!std::filesystem::exists("/dev/zero")) GTEST_SKIP() << "no /dev/zero";
  const auto t0 = std::chrono::steady_clock::now();
  try {
    scenario::readFile("/dev/zero");
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("larger than the 16.0 MB"), std::string::npos) << msg;
    EXPECT_NE(msg.find("/dev/zero"), std::string::npos) << msg;
  }
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 5.0);
}

TEST(ScenarioBadInput, UnknownKeysStopAtTheFirst) {
  std::string yaml = kBase + "extra:\n";
  for (int i = 0; i < 20000; ++i) yaml += "  k" + std::to_string(i) + ": 1\n";
  expectError(yaml, {"case.yaml:16:", "extra", "not a known field"});
}

TEST(StudyBadInput, DuplicateKeyInAStudyNamesBothLines) {
  const auto scen = tempFile("study_base.yaml"), study = tempFile("study.yaml");
  std::ofstream(scen) << kBase;
  std::ofstream(study) << "scenario: " << scen.filename().string()
                       << "\nmethod: grid\nmethod: list\nvary:\n  - field: needle.length\n    values: [100 mm]\n";
  try {
    study::readStudyFile(study);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find(study.string() + ":3:"), std::string::npos) << msg;
    EXPECT_NE(msg.find("key 'method' given twice (lines 2 and 3)"), std::string::npos) << msg;
  }
  std::filesystem::remove(scen);
  std::filesystem::remove(study);
}

TEST(StudyBadInput, DuplicateKeyInTheBaseScenarioIsNamedAtItsLine) {
  study::StudySpec spec;
  spec.file = "study.yaml";
  spec.scenario_file = "base.yaml";
  spec.method = study::Method::Grid;
  study::Parameter p;
  p.field = "needle.length";
  p.values = {"100 mm"};
  spec.parameters = {p};
  const std::string base = kBase + "needle: {outer_diameter: 20 G, length: 90 mm}\n";
  try {
    study::expandCases(spec, base);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("base.yaml:16:"), std::string::npos) << msg;
    EXPECT_NE(msg.find("key 'needle' given twice (lines 10 and 16)"), std::string::npos) << msg;
  }
}

TEST(StudyAliases, EditingOneAliasedPathLeavesTheOtherAsItWas) {
  const std::string base = R"(name: t
tissue:
  block: {length: 55 mm, width: 120 mm, height: 80 mm}
  layers:
    - thickness: 20 mm
      material: {law: linear, E: 30 kPa, nu: 0.4}
      friction: &f {C_p: 3 N/m, b_p: 200 N s/m^2}
    - thickness: 35 mm
      material: {law: linear, E: 30 kPa, nu: 0.4}
      friction: *f
needle: {outer_diameter: 18 G, length: 150 mm}
insertion:
  profile:
    - insert: &ins {to: 60 mm, speed: 3 mm/s}
)";
  study::Case c;
  c.index = 1;
  c.assignments = {{"tissue.layers[1].friction.C_p", "9 N/m"}};
  Scenario sc = scenario::readText(study::caseYaml(base, c), "case");
  EXPECT_DOUBLE_EQ(sc.tissue.layers[0].friction.C_p, 3.0);
  EXPECT_DOUBLE_EQ(sc.tissue.layers[1].friction.C_p, 9.0);
  EXPECT_DOUBLE_EQ(sc.tissue.layers[1].friction.b_p, 200.0);  // the rest of the alias is kept

  c.assignments = {{"tissue.layers[0].friction.C_p", "7 N/m"}, {"insertion.profile[0].insert.speed", "5 mm/s"}};
  sc = scenario::readText(study::caseYaml(base, c), "case");
  EXPECT_DOUBLE_EQ(sc.tissue.layers[0].friction.C_p, 7.0);
  EXPECT_DOUBLE_EQ(sc.tissue.layers[1].friction.C_p, 3.0);
  EXPECT_DOUBLE_EQ(sc.insertion.segments[0].speed, 0.005);

  // A field the base does not write is added to that place only.
  c.assignments = {{"tissue.layers[1].friction.coefficient", "0.3"}};
  sc = scenario::readText(study::caseYaml(base, c), "case");
  EXPECT_DOUBLE_EQ(sc.tissue.layers[1].friction.coefficient, 0.3);
  EXPECT_DOUBLE_EQ(sc.tissue.layers[0].friction.coefficient, 0.0);
}

TEST(ScenarioBadInput, MisspeltKeyNamesTheNearestKnownOne) {
  expectError(replaced(kBase, "  friction:", "  frcition:"),
              {"case.yaml:7:", "frcition", "did you mean 'friction'?", "allowed:"});
}

// Engines refuse fields after the reader (Scenario::where): the line of a given field, of a
// section's first given field, and the file alone for a default.
TEST(ScenarioBadInput, EngineRefusalsFindTheLineOfTheField) {
  const Scenario sc = scenario::readText(kBase, "case.yaml");
  EXPECT_EQ(sc.where("insertion.profile[0].insert.speed").str(), "case.yaml:15:34");
  EXPECT_EQ(sc.where("tissue.friction.C_p").str(), "case.yaml:8:10");
  EXPECT_EQ(sc.where("tissue.friction").line, 8);                  // a section: its first given field
  EXPECT_EQ(sc.where("tissue.friction.coefficient").line, 8);      // a default inside a given section
  EXPECT_EQ(sc.where("model.time_step").str(), "case.yaml");       // not given at all
}

TEST(ScenarioBadInput, AnInclusionNamingNoGroupOfTheGeometrySaysWhichItHas) {
  // a 20 x 20 mm square of four triangles: groups gel (1) and tumour (2)
  const auto mesh = tempFile("groups.msh");
  std::ofstream(mesh) << R"($MeshFormat
2.2 0 8
$EndMeshFormat
$PhysicalNames
2
2 1 "gel"
2 2 "tumour"
$EndPhysicalNames
$Nodes
5
1 0 -10 0
2 20 -10 0
3 20 10 0
4 0 10 0
5 10 0 0
$EndNodes
$Elements
4
1 2 2 1 1 1 2 5
2 2 2 1 1 2 3 5
3 2 2 1 1 3 4 5
4 2 2 2 2 4 1 5
$EndElements
)";
  const std::string yaml = R"(name: groups
tissue:
  geometry: {file: )" + mesh.string() + R"(, unit: mm}
  layers: [{name: gel, material: {law: neo-hookean, C10: 3.6 kPa, nu: 0.45}}]
  inclusions:
    - {target: true, name: tumour, material: {law: neo-hookean, C10: 16.6 kPa, nu: 0.45}}
needle: {outer_diameter: 2 mm, length: 40 mm}
insertion:
  profile:
    - insert: {to: 5 mm, speed: 10 mm/s}
model: {engine: explicit, explicit: {dimension: 2d}}
)";
  EXPECT_NO_THROW(scenario::readText(yaml, "case.yaml"));
  expectError(replaced(yaml, "name: tumour", "name: tumor"),
              {"case.yaml:6:", "tissue.inclusions[0].name", "tumor", "did you mean 'tumour'?", "gel, tumour"});
  std::filesystem::remove(mesh);
}
