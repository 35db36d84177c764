#pragma once
// The results folder of a run: summary.json, <table>.csv and report.html.
// Everything is staged in a hidden sibling folder and moved into place only
// when complete, so a failed run never leaves a half-written folder and an
// existing folder is never silently overwritten.
#include <chrono>
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "needlesim/results/result_sink.hpp"
#include "needlesim/scenario/scenario.hpp"
#include "needlesim/io/field_series.hpp"

namespace needlesim::io {

struct KeyResult {
  std::string key;
  double value;
  std::string unit;
  std::string meaning;
};

class ResultsFolder : public ResultSink {
 public:
  // target: normalised with outputPath. printWarnings: each warning on stderr as it is raised.
  ResultsFolder(const Scenario& scenario, std::filesystem::path target, bool printWarnings = false);

  void table(const std::string& name, Table table) override;
  void result(const std::string& key, double value, const std::string& unit, const std::string& meaning) override;
  void plot(Plot plot) override;
  void note(const std::string& text) override;
  void warning(const std::string& text) override;
  FieldSeries* fields(const std::string& name, int dim) override;

  // Writes everything and moves the folder into place; `replace` allows an
  // existing needlesim results folder (isResultsFolder) to be replaced, only
  // after the new one is complete; anything else at the target is refused.
  // A run that stopped early commits what it has with its `failure` message.
  // A write that fails (disk full) throws Error naming the file and commits
  // nothing (the destructor removes the staging folder).
  void commit(bool replace, double wall_seconds, const std::string& failure = {});
  ~ResultsFolder() override;

  const std::vector<KeyResult>& results() const { return results_; }
  const std::vector<std::pair<std::string, Table>>& tables() const { return tables_; }
  const std::filesystem::path& target() const { return target_; }
  // The files commit wrote into the folder (summary.json's "files").
  const std::vector<std::string>& files() const { return files_; }

 private:
  const Scenario& scenario_;
  std::filesystem::path target_;
  std::vector<std::pair<std::string, Table>> tables_;
  std::vector<KeyResult> results_;
  std::vector<Plot> plots_;
  std::vector<std::string> notes_;
  std::vector<std::string> warnings_;
  bool printWarnings_ = false;
  std::filesystem::path stage_;
  std::vector<std::unique_ptr<FieldSeries>> fields_;
  std::vector<std::string> field_names_;
  bool committed_ = false;
  std::vector<std::string> files_;

  nlohmann::json writeTables() const;  // <table>.csv; the names written
  nlohmann::json summaryJson(const nlohmann::json& files, double wall_seconds, const std::string& failure) const;
  HtmlReport report(double wall_seconds, const std::string& failure) const;
  void moveIntoPlace();
};

// --out or output.directory as a results target: lexically normal, without a
// trailing separator ("out/" and "out/." are "out"). InputError for a path
// with no folder name ("", ".", "..", "/").
std::filesystem::path outputPath(const std::filesystem::path& given, const std::string& field, const SourceLocation& where);

// Whether `dir` is a folder needlesim wrote: it holds a summary.json (`run`) or
// fit.json (`fit`) with the "needlesim" version record and a "status". Only such
// a folder may be replaced.
bool isResultsFolder(const std::filesystem::path& dir);

// What is at `path`, for messages: "a file", "an empty folder", "a folder
// holding thesis.tex, figures/ and 3 more".
std::string describeContents(const std::filesystem::path& path);

// Before a run: InputError naming `field` (--out, output.directory) when the
// target cannot be written: a name too long for the file system (with the
// staging and checkpoint suffixes), a path over PATH_MAX, a parent folder that
// cannot be created or written (checked by creating and removing a probe file),
// or, with `overwrite`, something at the target that is not a results folder.
void checkOutputTarget(const std::filesystem::path& target, const std::string& field, const std::string& source,
                       bool overwrite);

// The staging folders (.<name>.partial-<pid>) in `parent` whose process no
// longer runs (a run killed with SIGKILL, or a power cut): removed before a
// run writes into `parent`. Only folders named exactly so are touched;
// returns how many were removed.
int removeStaleStages(const std::filesystem::path& parent);

// results/<name>, or results/<name>-2, -3, ... if taken.
std::filesystem::path freeResultsPath(const std::filesystem::path& base);

// The folder a command writes its results to, checked before the work starts
// (checkOutputTarget). `chosen` is the folder a user named with `field`
// ("--out", "output.directory") at `where`: one that exists is refused unless
// `overwrite` (and then only a results folder may be replaced). Without a
// chosen folder (empty `field`), `chosen` is the automatic results/<name>, and
// the first free name of freeResultsPath is returned.
std::filesystem::path resolveResultsTarget(const std::filesystem::path& chosen, const std::string& field,
                                           const SourceLocation& where, bool overwrite);

// The hidden staging folder of `target`: .<name>.partial-<pid> beside it.
std::filesystem::path stagingFolder(const std::filesystem::path& target);

// Error unless `target` is free, or `replace` is given and it is a results
// folder (isResultsFolder): what a commit checks before it writes.
void checkReplaceable(const std::filesystem::path& target, bool replace);

// The complete staging folder `stage` becomes `target`; a results folder at
// the target (checkReplaceable) is moved aside first and deleted only once the
// new one is in place.
void moveStageIntoPlace(const std::filesystem::path& stage, const std::filesystem::path& target);

// The scenario as understood (Scenario::understood): every field in the scenario
// file's schema, quantities in SI with their unit; `needlesim run summary.json`
// reads it again. null for a Scenario built in code.
nlohmann::json scenarioToJson(const Scenario& scenario);

}  // namespace needlesim::io
