// Field paths of studies and with_values: the strict grammar, the schema's
// keys (with the nearest one for a typo), the base scenario's list lengths,
// errors with the study file's line; the case limit, representative cases of
// `check`, and a scenario that is a folder.
#include <gtest/gtest.h>

#include <array>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <sys/wait.h>

#include "needlesim/core/error.hpp"
#include "needlesim/core/nearest_name.hpp"
#include "needlesim/study/field_path.hpp"
#include "needlesim/study/study.hpp"
#include "../app/cli_run.hpp"

using namespace needlesim;
using namespace needlesim::study;
namespace fs = std::filesystem;

namespace {

fs::path scratch(const std::string& name) {
  fs::path d = fs::temp_directory_path() / ("needlesim_paths_" + std::to_string(::getpid())) / name;
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

std::string example() { return std::string(NEEDLESIM_SOURCE_DIR) + "/examples/gelatin_18G_3mms.yaml"; }

std::string readAll(const fs::path& f) {
  std::ifstream in(f);
  return {std::istreambuf_iterator<char>(in), {}};
}

// A study whose first parameter's field path is on line 4.
fs::path studyWithPath(const fs::path& dir, const std::string& path) {
  fs::path f = dir / "study.yaml";
  std::ofstream(f) << "scenario: " << example() << "\n"
                   << "directory: " << (dir / "out").string() << "\n"
                   << "vary:\n"
                   << "  - field: \"" << path << "\"\n"
                   << "    values: [4 mm/s]\n";
  return f;
}

// The message of the InputError that reading and expanding the study throws ("" if none).
std::string studyError(const fs::path& f) {
  try {
    StudySpec spec = readStudyFile(f);
    expandCases(spec, readAll(spec.scenario_file), CaseCheck::Representative);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

FieldPathError pathError(const std::string& path) {
  try {
    parseScenarioFieldPath(path);
  } catch (const FieldPathError& e) {
    return e;
  }
  ADD_FAILURE() << "no error for " << path;
  return FieldPathError(0, "", "");
}

void expectHas(const std::string& text, const std::vector<std::string>& parts) {
  for (const auto& p : parts) EXPECT_NE(text.find(p), std::string::npos) << "'" << p << "' not in: " << text;
}

using needlesim::test::CliResult;
using needlesim::test::runCli;

}  // namespace

TEST(NearestName, FindsTheKnownNameOfATypo) {
  const std::vector<std::string> known{"profile", "entry_angle", "entry_offset", "speed"};
  EXPECT_EQ(nearestName("profle", known), "profile");
  EXPECT_EQ(nearestName("sped", known), "speed");
  EXPECT_EQ(nearestName("entry_ofset", known), "entry_offset");
  EXPECT_EQ(nearestName("Profile", known), "profile");
  EXPECT_EQ(nearestName("xyz", known), "");  // nothing close
  EXPECT_EQ(editDistance("abcd", "abdc"), 1u);  // a swap of neighbours is one edit
}

TEST(StudyFieldPath, SplitsKeysAndIndicesWithTheirPositions) {
  auto steps = parseScenarioFieldPath("insertion.profile[12].insert.speed");
  ASSERT_EQ(steps.size(), 4u);
  EXPECT_EQ(steps[1].key, "profile");
  ASSERT_TRUE(steps[1].index.has_value());
  EXPECT_EQ(*steps[1].index, 12u);
  EXPECT_EQ(steps[1].key_position, 11u);
  EXPECT_EQ(steps[1].index_position, 19u);
  EXPECT_FALSE(steps[3].index.has_value());
}

TEST(StudyFieldPath, GrammarErrorsNameThePositionAndWhatIsAllowed) {
  auto e = pathError("insertion.profile[x].insert.speed");
  EXPECT_EQ(e.position(), 19u);
  expectHas(e.what(), {"'x' is not an index", "whole number"});
  e = pathError("insertion.profile[-1].insert.speed");
  EXPECT_EQ(e.position(), 19u);
  expectHas(e.what(), {"'-1' is not an index", "no sign"});
  e = pathError("insertion.profile[0]junk.insert.speed");
  EXPECT_EQ(e.position(), 21u);
  expectHas(e.what(), {"'junk' follows ']'", "'.'"});
  e = pathError("insertion.profile[99999999999999999999999].insert.speed");
  EXPECT_EQ(e.position(), 19u);
  expectHas(e.what(), {"index 99999999999999999999999 is too large"});
  e = pathError("insertion.profile[0");
  expectHas(e.what(), {"']' must close it"});
  e = pathError("insertion..profile");
  EXPECT_EQ(e.position(), 11u);
  expectHas(e.what(), {"follows '.' where a field name must start"});
  e = pathError("tissue.friction.C p");
  EXPECT_EQ(e.position(), 18u);
  expectHas(e.what(), {"' ' is not allowed in a field name"});
  e = pathError("");
  expectHas(e.what(), {"the path is empty"});
  e = pathError("tissue.\x1b[2Jfriction");
  expectHas(e.what(), {"\\x1b"});  // a control byte is escaped, never echoed
}

TEST(StudyFieldPath, SchemaErrorsNameTheNearestKeyAndTheKeysAllowed) {
  auto e = pathError("insertion.profle[0].insert.speed");
  EXPECT_EQ(e.position(), 11u);
  expectHas(e.what(), {"'profle' is not a field of section 'insertion'", "did you mean 'profile'?", "entry_angle"});
  e = pathError("insertion.profile[0].insert.sped");
  expectHas(e.what(), {"did you mean 'speed'?", "to, speed, spin_rate"});
  e = pathError("insertion.profile.insert.speed");
  expectHas(e.what(), {"'profile' is a list", "profile[0]"});
  e = pathError("tissue.friction[0].C_p");
  expectHas(e.what(), {"'friction' is not a list"});
  e = pathError("tissue.friction.C_p.x");
  expectHas(e.what(), {"'C_p' is a single value", "tissue.friction.C_p"});
  e = pathError("insertion.profile[0].insert");
  expectHas(e.what(), {"'insert' is a section", "speed"});
  EXPECT_NO_THROW(parseScenarioFieldPath("tissue.material"));  // a library name
  EXPECT_NO_THROW(parseScenarioFieldPath("tissue.layers[1].material.E"));
}

TEST(StudyFieldPath, StudyErrorsGiveFileLineFieldAndPosition) {
  fs::path dir = scratch("study_errors");
  struct Case {
    std::string path;
    std::vector<std::string> parts;
  };
  const std::vector<Case> cases{
      {"insertion.profile[99999999999].insert.speed",
       {"has no entry [99999999999] in the base scenario (3 entries)", "an index from 0 to 2", "character 19"}},
      {"insertion.profile[x].insert.speed", {"'x' is not an index", "character 19"}},
      {"insertion.profile[-1].insert.speed", {"'-1' is not an index"}},
      {"insertion.profile[0]junk.insert.speed", {"'junk' follows ']'", "character 21"}},
      {"insertion.profle[0].insert.speed", {"did you mean 'profile'?", "character 11"}},
      {"tissue.layers[0].thickness", {"'layers' is not a list in the base scenario"}},
  };
  for (const auto& c : cases) {
    std::string msg = studyError(studyWithPath(dir, c.path));
    ASSERT_FALSE(msg.empty()) << c.path;
    expectHas(msg, {"study.yaml:4:", "vary[0].field", "is not a field path of the scenario", c.path});
    expectHas(msg, c.parts);
    EXPECT_EQ(msg.find("stoi"), std::string::npos) << msg;
  }
  EXPECT_EQ(studyError(studyWithPath(dir, "insertion.profile[0].insert.speed")), "");
}

TEST(StudyFieldPath, ScenarioOrStudyThatIsAFolderIsNamed) {
  fs::path dir = scratch("folder");
  fs::create_directories(dir / "scen");
  std::ofstream(dir / "study.yaml") << "scenario: scen\nvary:\n  - {field: tissue.friction.C_p, values: [3 N/m]}\n";
  expectHas(studyError(dir / "study.yaml"), {"study.yaml:1:", "scenario", "is a folder", "give a scenario file"});
  expectHas(studyError(dir / "scen"), {"scen", "is a folder", "a study file"});
}

TEST(StudyFieldPath, CaseCountIsBounded) {
  fs::path dir = scratch("limit");
  fs::path f = dir / "study.yaml";
  std::ofstream(f) << "scenario: " << example() << "\nmethod: latin-hypercube\nsamples: 1e6\nvary:\n"
                   << "  - {field: tissue.friction.C_p, min: 2 N/m, max: 4 N/m}\n";
  expectHas(studyError(f), {"study.yaml:3:", "samples", "100000"});
  std::string many = "[";
  for (int i = 0; i < 400; ++i) many += (i ? ", " : "") + std::to_string(2 + i * 0.001) + " N/m";
  many += "]";
  std::ofstream(f) << "scenario: " << example() << "\nvary:\n  - {field: tissue.friction.C_p, values: " << many
                   << "}\n  - {field: tissue.friction.b_p, values: " << many << "}\n";
  expectHas(studyError(f), {"study.yaml:3:", "vary", "more than 100000 cases", "at most 100000"});
  std::ofstream(f) << "scenario: " << example() << "\nmethod: latin-hypercube\nsamples: 2.5\nvary:\n"
                   << "  - {field: tissue.friction.C_p, min: 2 N/m, max: 4 N/m}\n";
  expectHas(studyError(f), {"study.yaml:3:", "samples", "whole number"});
  std::ofstream(f) << "scenario: " << example() << "\nvary: []\n";
  expectHas(studyError(f), {"study.yaml:2:", "vary", "empty"});
}

TEST(StudyFieldPath, CheckReadsRepresentativeCasesOnly) {
  fs::path dir = scratch("representative");
  fs::path f = dir / "study.yaml";
  std::ofstream(f) << "scenario: " << example() << "\nmethod: latin-hypercube\nsamples: 100000\nvary:\n"
                   << "  - {field: tissue.friction.C_p, min: 2 N/m, max: 4 N/m}\n"
                   << "  - {field: \"insertion.profile[0].insert.speed\", min: 1 mm/s, max: 5 mm/s}\n";
  auto start = std::chrono::steady_clock::now();
  CliResult r = runCli("check " + f.string());
  double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_EQ(r.code, 0) << r.out;
  expectHas(r.out, {"ok", "study of 100000 cases", "read as scenarios"});
  EXPECT_LT(seconds, 30.0);

  // A grid value with a wrong unit in the middle of a list is among the cases read.
  std::ofstream(f) << "scenario: " << example() << "\nvary:\n"
                   << "  - {field: tissue.friction.C_p, values: [2 N/m, 3 mm, 4 N/m]}\n"
                   << "  - {field: tissue.friction.b_p, values: [200 N*s/m^2, 300 N*s/m^2]}\n";
  r = runCli("check " + f.string());
  EXPECT_EQ(r.code, 2) << r.out;
  expectHas(r.out, {"study.yaml:3:", "tissue.friction.C_p = 3 mm", "wrong unit"});  // the line that sets C_p
}

// Seeded mutations of valid paths: the parser answers FieldPathError or a
// path, never another exception, a crash or a hang.
TEST(StudyFieldPath, MutatedPathsGiveFieldPathErrorsOnly) {
  const std::vector<std::string> seeds{"insertion.profile[0].insert.speed", "tissue.layers[1].material.E",
                                       "tissue.friction.C_p", "model.mpm.markers[2].x"};
  const std::string alphabet = "ab_Z09.[]-: \x01\xff";
  std::mt19937 rng(19);
  int accepted = 0;
  for (int i = 0; i < 20000; ++i) {
    std::string p = seeds[rng() % seeds.size()];
    for (int k = 1 + static_cast<int>(rng() % 3); k > 0; --k) {
      std::size_t at = rng() % (p.size() + 1);
      switch (rng() % 3) {
        case 0: p.insert(at, 1, alphabet[rng() % alphabet.size()]); break;
        case 1: if (at < p.size()) p.erase(at, 1); break;
        default: if (at < p.size()) p[at] = alphabet[rng() % alphabet.size()];
      }
    }
    try {
      parseScenarioFieldPath(p);
      ++accepted;
    } catch (const FieldPathError& e) {
      ASSERT_GE(e.position(), 1u) << p;
      ASSERT_LE(e.position(), p.size() + 1) << p;
    }
  }
  EXPECT_GT(accepted, 0);
}

// `check` reads representative cases; every case of every shipped study is a valid scenario.
TEST(StudyFieldPath, EveryCaseOfEveryShippedStudyIsValid) {
  int studies = 0;
  for (const auto& e : fs::directory_iterator(std::string(NEEDLESIM_SOURCE_DIR) + "/examples/studies")) {
    if (e.path().extension() != ".yaml") continue;
    StudySpec spec = readStudyFile(e.path());
    EXPECT_NO_THROW(expandCases(spec, readAll(spec.scenario_file), CaseCheck::All)) << e.path();
    ++studies;
  }
  EXPECT_GT(studies, 5);
}
