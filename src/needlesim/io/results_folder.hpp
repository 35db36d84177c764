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

#include "needlesim/engines/engine.hpp"
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
  ResultsFolder(const Scenario& scenario, std::filesystem::path target);

  void table(const std::string& name, Table table) override;
  void result(const std::string& key, double value, const std::string& unit, const std::string& meaning) override;
  void plot(Plot plot) override;
  void note(const std::string& text) override;
  FieldSeries* fields(const std::string& name, int dim) override;

  // Writes everything and moves the folder into place; `replace` allows an
  // existing target to be replaced (only after the new one is complete).
  // A run that stopped early commits what it has with its `failure` message.
  void commit(bool replace, double wall_seconds, const std::string& failure = {});
  ~ResultsFolder() override;

  const std::vector<KeyResult>& results() const { return results_; }
  const std::vector<std::pair<std::string, Table>>& tables() const { return tables_; }
  const std::filesystem::path& target() const { return target_; }

 private:
  const Scenario& scenario_;
  std::filesystem::path target_;
  std::vector<std::pair<std::string, Table>> tables_;
  std::vector<KeyResult> results_;
  std::vector<Plot> plots_;
  std::vector<std::string> notes_;
  std::filesystem::path stage_;
  std::vector<std::unique_ptr<FieldSeries>> fields_;
  std::vector<std::string> field_names_;
  bool committed_ = false;
};

// results/<name>, or results/<name>-2, -3, ... if taken.
std::filesystem::path freeResultsPath(const std::filesystem::path& base);

// The scenario as understood (Scenario::understood): every field in the scenario
// file's schema, quantities in SI with their unit; `needlesim run summary.json`
// reads it again. null for a Scenario built in code.
nlohmann::json scenarioToJson(const Scenario& scenario);

}  // namespace needlesim::io
