#pragma once
// Parameter studies (`needlesim sweep`): one base scenario, the fields to
// vary, a sampling method; every case runs through the same scenario reader
// and engine as `needlesim run`, so a study works with any engine.
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "needlesim/core/units.hpp"
#include "needlesim/scenario/study_section.hpp"

namespace needlesim::study {

// Method, Parameter, StudySpec and kMaxCases: the study file's fields (scenario/study_section.hpp).

// One case: the field assignments (value texts with units) applied to the base scenario.
struct Case {
  int index = 0;  // 1-based
  std::vector<std::pair<std::string, std::string>> assignments;
  std::vector<double> values_si;  // one per parameter, SI (NaN if not numeric)
};

StudySpec readStudyFile(const std::filesystem::path& path);
// True when the file is YAML with a top-level 'vary' list (a study, not a scenario).
bool isStudyFile(const std::filesystem::path& path);
// Which cases expandCases reads as scenarios: all (before a sweep runs), or
// the representative ones (needlesim check, bounded by the study file's size).
enum class CaseCheck { All, Representative };
// Expands the sampling method into cases; needs the base scenario text for
// one-at-a-time (base values) and checks the field paths against it and the
// case scenarios as `check` says.
std::vector<Case> expandCases(const StudySpec& spec, const std::string& baseYaml, CaseCheck check = CaseCheck::All);
// The most cases `needlesim check` reads as scenarios.
inline constexpr std::size_t kMaxCheckedCases = 200;
// Indices (0-based, at most kMaxCheckedCases) of the first case, of the cases
// with each field's smallest and largest value, and of the first case of each
// unit (or each non-numeric word, such as a material name) per field.
std::vector<std::size_t> representativeCases(const StudySpec& spec, const std::vector<Case>& cases);
// Throws FieldPathError when `path` breaks the grammar or the schema or leads
// to no place in the base scenario (a list entry it does not write).
void checkFieldPath(const std::string& baseYaml, const std::string& path);
// The base scenario YAML with a case's assignments applied.
std::string caseYaml(const std::string& baseYaml, const Case& c);

struct SweepOptions {
  bool progress = true;
  bool resume = false;  // reuse cases whose folder is complete
  bool overwrite = false;  // replace an earlier study in the study folder (only a study folder, isStudyFolder)
  std::filesystem::path out;  // --out: the study folder, over the study file's `directory`
  int rank = 0, ranks = 1;  // MPI: this process runs cases with (index - 1) % ranks == rank
};

struct SweepReport {
  std::filesystem::path folder;
  int cases = 0, ran = 0, reused = 0;
  std::vector<int> failed;  // case indices that failed (rerun with --resume)
  std::string overview;     // the inputs, outputs and constants for the terminal (studyOverview)
  std::vector<std::string> notes;  // folders left or set aside (also printed on stderr as they happen)
};

// Whether `dir` holds nothing but the names a sweep writes (cases/ with case
// folders, their error files, staging folders and kept folders case_NNNN.kept-K;
// study.csv, study.json, report.html): a folder a sweep may resume in or
// clear. An empty folder is one.
bool isStudyFolder(const std::filesystem::path& dir);

// Runs the cases of this rank, then (rank 0) gathers every case's summary
// into study.csv, study.json and report.html in the study folder. The study
// folder is options.out (--out), else the study file's `directory`, else
// results/<name>, checked like a run's results folder (checkOutputTarget) and
// locked (io::FolderLock, shared by the ranks of an MPI study) until the
// study is gathered: a folder another needlesim writes is refused. One that
// exists is used with options.resume or cleared with options.overwrite (both
// only if isStudyFolder) and refused otherwise. --overwrite deletes only
// study.csv, study.json, report.html, error files, dead processes' staging
// folders and the files each case's summary.json lists; a case folder left
// holding anything else is renamed case_NNNN.kept-K and named (a note). A case
// folder without a readable summary.json is set aside the same way and its
// case runs again. Filesystem and JSON failures are Error naming the folder.
SweepReport runSweep(const StudySpec& spec, const SweepOptions& options);
void gatherSweep(const StudySpec& spec, const std::vector<Case>& cases, SweepReport& report);

}  // namespace needlesim::study
