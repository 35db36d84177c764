#pragma once
// How a study's results are shown in study.csv, report.html and on the
// terminal: the varied parameters are the inputs (in the study file's order),
// apart from the outputs (the cases' key results); an output with one value
// over every complete case is named once as a constant and left out of the
// report's table and plots (study.csv keeps every column).
#include <cstddef>
#include <string>
#include <vector>

#include "needlesim/core/units.hpp"
#include "needlesim/io/html_report.hpp"
#include "needlesim/io/table.hpp"
#include "needlesim/study/study.hpp"

namespace needlesim::study {

// Relative difference below which two values of an output count as the same.
inline constexpr double kConstantTolerance = 1e-12;

// A study's gathered results: table is study.csv, one row per case with the
// columns "case", "complete", the inputs (inputColumnName of each varied
// field) and the outputs (one per result key, in first-seen order).
struct StudyResults {
  const StudySpec& spec;
  const std::vector<Case>& cases;
  io::Table table;
  // The units values are shown in (the cases' output.units); study.csv keeps SI.
  units::DisplayUnits display = {};
};

// The CSV column name of a varied field: "input: tissue.friction.C_p".
std::string inputColumnName(const std::string& field);

// The column of the first output (after case, complete and the inputs).
std::size_t firstOutputColumn(const StudyResults& r);

// Whether the output values of the complete cases are one value: at least two
// of them, every one finite and within kConstantTolerance (relative) of the first.
bool constantOverCases(const std::vector<double>& values);

// The output columns (table indices) that change over the complete cases, and
// those that are constant over them (constantOverCases).
struct OutputColumns {
  std::vector<std::size_t> varying;
  std::vector<std::size_t> constant;
};
OutputColumns splitOutputs(const StudyResults& r);

// "constant over all cases: punctures = 1, peak_force_depth = 0.055 m"; empty
// when no output is constant.
std::string constantLine(const StudyResults& r, const OutputColumns& outputs);

// One line per varied field: how many values it takes and which: up to 8 as
// written in the study file (or by the sampler), "4 values: 2.5 mm/s, 3.33
// mm/s, 5 mm/s, 10 mm/s"; more numbers by their smallest and largest, "40
// values: from 0.0276861 N to 0.0672617 N".
std::vector<std::string> inputLines(const StudyResults& r);

// The report.html of the study: the inputs and the constants as facts, a
// table of the cases with the inputs and the varying outputs as separate
// column groups, and each varying output against each input.
io::HtmlReport studyReport(const StudyResults& r, const std::vector<int>& missing);

// What the terminal shows after a sweep: the inputs, the range of each varying
// output over the complete cases, and the constant line.
std::string studyOverview(const StudyResults& r);

// The most case rows report.html lists (study.csv has every case).
inline constexpr std::size_t kMaxReportRows = 500;

}  // namespace needlesim::study
