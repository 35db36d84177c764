#pragma once
// The study file of `needlesim sweep` (docs/studies.md): a base scenario, the fields to vary and
// the sampling method. Plain structs; each field is declared once in study_section.cpp
// (scenario/parameter_table.hpp), where the schema, `needlesim schema` and the study reader
// (study/study_reader.cpp) take it from. A study file is no scenario: nothing of it is recorded.
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "needlesim/core/units.hpp"
#include "needlesim/scenario/parameter_table.hpp"

namespace needlesim::study {

enum class Method { Grid, OneAtATime, LatinHypercube, List };

struct Parameter {
  std::string field;                // path in the scenario, e.g. tissue.friction.C_p, insertion.profile[0].insert.speed
  std::vector<std::string> values;  // Grid / List: values as a user writes them ("3 N/m")
  std::vector<double> percent;      // OneAtATime: changes of the base value in percent
  std::string min_text, max_text;   // LatinHypercube: the bounds as written
  double min = 0.0, max = 0.0;      // LatinHypercube, SI
  units::Dim dim{};                 // dimension of min/max
  int line = 0, column = 0;         // where its field path is written in the study file
};

struct StudySpec {
  std::string name;                     // empty in the file: the study file's name
  std::filesystem::path file;           // the study file
  std::filesystem::path scenario_file;  // base scenario (resolved relative to the study file)
  Method method = Method::Grid;
  std::vector<Parameter> parameters;
  int samples = 10;         // LatinHypercube
  std::uint64_t seed = 1;   // LatinHypercube
  int parallel = 0;         // worker threads per process (0 = all cores)
  std::string directory;    // study folder (default results/<name>)
};

// The most cases a study may have (grid products, one-at-a-time, samples).
inline constexpr std::uint64_t kMaxCases = 100000;

}  // namespace needlesim::study

namespace needlesim::scenario {

// The study file's top level (section type `study`); reading it needs StudySpec::file set.
const ParamTable<study::StudySpec>& studyFileTable();
// One entry of its `vary` list (section type `parameter`).
const ParamTable<study::Parameter>& studyParameterTable();

}  // namespace needlesim::scenario
