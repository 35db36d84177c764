#include "needlesim/io/results_folder.hpp"

#include <fmt/format.h>
#include <unistd.h>

#include <cmath>

#include "needlesim/core/error.hpp"
#include "needlesim/core/version.hpp"
#include "needlesim/io/atomic_file.hpp"

namespace needlesim::io {
namespace fs = std::filesystem;

namespace {

nlohmann::json safeNumber(double v) {
  if (std::isfinite(v)) return v;
  return nullptr;  // never write NaN into JSON
}
}  // namespace

nlohmann::json scenarioToJson(const Scenario& sc) {
  if (sc.understood.empty()) return nullptr;  // built in code: no scenario document exists
  return nlohmann::json::parse(sc.understood);
}

fs::path freeResultsPath(const fs::path& base) {
  if (!fs::exists(base)) return base;
  for (int i = 2; i < 10000; ++i) {
    fs::path p = base;
    p += fmt::format("-{}", i);
    if (!fs::exists(p)) return p;
  }
  throw Error("no free results folder name next to " + base.string());
}

ResultsFolder::ResultsFolder(const Scenario& scenario, fs::path target)
    : scenario_(scenario), target_(std::move(target)) {
  fs::path parent = target_.has_parent_path() ? target_.parent_path() : fs::path(".");
  stage_ = parent / fmt::format(".{}.partial-{}", target_.filename().string(), ::getpid());
}

ResultsFolder::~ResultsFolder() {
  fields_.clear();
  if (!committed_) {
    std::error_code ec;
    fs::remove_all(stage_, ec);
  }
}

FieldSeries* ResultsFolder::fields(const std::string& name, int dim) {
  fs::create_directories(stage_);
  fields_.push_back(std::make_unique<FieldSeries>(stage_ / (name + ".h5"), stage_ / (name + ".xdmf"), dim));
  field_names_.push_back(name);
  return fields_.back().get();
}

void ResultsFolder::table(const std::string& name, Table t) { tables_.emplace_back(name, std::move(t)); }

void ResultsFolder::result(const std::string& key, double value, const std::string& unit,
                           const std::string& meaning) {
  results_.push_back({key, value, unit, meaning});
}

void ResultsFolder::plot(Plot p) { plots_.push_back(std::move(p)); }
void ResultsFolder::note(const std::string& text) { notes_.push_back(text); }

void ResultsFolder::commit(bool replace, double wall_seconds, const std::string& failure) {
  if (fs::exists(target_) && !replace)
    throw Error("results folder " + target_.string() +
                " already exists; choose another with --out or pass --overwrite to replace it");
  fs::path parent = target_.has_parent_path() ? target_.parent_path() : fs::path(".");
  fs::create_directories(parent);
  const fs::path& stage = stage_;
  fs::create_directories(stage);
  fields_.clear();  // closes the HDF5 files

  nlohmann::json files = nlohmann::json::array();
  if (scenario_.output.csv)
    for (const auto& [name, t] : tables_) {
      writeFileAtomic(stage / (name + ".csv"), t.csv());
      files.push_back(name + ".csv");
    }
  nlohmann::json res = nlohmann::json::object();
  for (const auto& r : results_)
    res[r.key] = {{"value", safeNumber(r.value)}, {"unit", r.unit}, {"meaning", r.meaning}};
  for (const auto& f : field_names_) {
    files.push_back(f + ".xdmf");
    files.push_back(f + ".h5");
  }
  if (scenario_.output.html) files.push_back("report.html");
  files.push_back("summary.json");
  nlohmann::json summary = {{"needlesim", {{"version", kVersion}, {"git_revision", kGitRevision}}},
                            {"engine", scenario_.model.engine},
                            {"status", failure.empty() ? "complete" : "stopped"},
                            {"stopped_because", failure.empty() ? nlohmann::json(nullptr) : nlohmann::json(failure)},
                            {"wall_time", {{"value", wall_seconds}, {"unit", "s"}}},
                            {"results", res},
                            {"notes", notes_},
                            {"files", files},
                            {"scenario_source", scenario_.source},
                            {"scenario", scenarioToJson(scenario_)}};
  writeFileAtomic(stage / "summary.json", summary.dump(2) + "\n");

  if (scenario_.output.html) {
    HtmlReport rep;
    rep.title = "needlesim: " + scenario_.name;
    rep.subtitle = scenario_.description.empty() ? scenario_.source : scenario_.description;
    rep.facts.emplace_back("engine", scenario_.model.engine);
    rep.facts.emplace_back("scenario", scenario_.source);
    if (!failure.empty()) rep.facts.emplace_back("STOPPED", failure);
    for (const auto& r : results_)
      rep.facts.emplace_back(r.key + " (" + r.meaning + ")",
                             std::isfinite(r.value) ? fmt::format("{:.6g} {}", r.value, r.unit == "1" ? "" : r.unit)
                                                    : "n/a");
    rep.facts.emplace_back("wall time", fmt::format("{:.3f} s", wall_seconds));
    rep.plots = plots_;
    rep.notes = notes_;
    writeFileAtomic(stage / "report.html", rep.render());
  }

  if (fs::exists(target_)) {
    fs::path old = parent / fmt::format(".{}.old-{}", target_.filename().string(), ::getpid());
    fs::rename(target_, old);
    fs::rename(stage, target_);
    fs::remove_all(old);
  } else {
    fs::rename(stage, target_);
  }
  committed_ = true;
}

}  // namespace needlesim::io
