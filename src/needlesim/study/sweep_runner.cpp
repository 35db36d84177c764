#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <atomic>
#include <cmath>
#include <fstream>
#include <map>
#include <mutex>
#include <sstream>
#include <thread>

#include "needlesim/core/error.hpp"
#include "needlesim/core/progress.hpp"
#include "needlesim/engines/run_scenario.hpp"
#include "needlesim/io/atomic_file.hpp"
#include "needlesim/io/html_report.hpp"
#include "needlesim/io/table.hpp"
#include "needlesim/results/display_units.hpp"
#include "needlesim/scenario/reader.hpp"
#include "needlesim/study/study.hpp"

namespace needlesim::study {
namespace fs = std::filesystem;

namespace {

std::string readText(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

fs::path studyFolder(const StudySpec& spec) {
  return spec.directory.empty() ? fs::path("results") / spec.name : fs::path(spec.directory);
}

fs::path caseFolder(const fs::path& study, int index) { return study / "cases" / fmt::format("case_{:04d}", index); }

bool caseComplete(const fs::path& folder) { return fs::exists(folder / "summary.json"); }

// A failed case's message in cases/case_NNNN.error.txt; a write that fails (a full disk) is kept in
// `unrecorded` for the sweep to report once its workers have stopped.
void recordCaseError(const fs::path& study, int index, const std::string& what, std::vector<std::string>& unrecorded) {
  try {
    io::writeFileAtomic(study / "cases" / fmt::format("case_{:04d}.error.txt", index), what + "\n");
  } catch (const std::exception& e) {
    unrecorded.push_back(fmt::format("case {}: {} ({})", index, what, e.what()));
  }
}

}  // namespace

SweepReport runSweep(const StudySpec& spec, const SweepOptions& opt) {
  std::string baseYaml = readText(spec.scenario_file);
  std::vector<Case> cases = expandCases(spec, baseYaml);
  SweepReport rep;
  rep.folder = studyFolder(spec);
  rep.cases = static_cast<int>(cases.size());
  if (opt.rank == 0 && fs::exists(rep.folder / "study.json") && !opt.resume)
    throw InputError(SourceLocation{spec.file.string(), 0, 0}, "directory", rep.folder.string(),
                     "the study folder already holds a finished study",
                     "another directory, or --resume to reuse its completed cases");
  fs::create_directories(rep.folder / "cases");

  // This rank's cases; completed ones are reused on --resume.
  std::vector<const Case*> todo;
  for (const auto& c : cases) {
    if ((c.index - 1) % opt.ranks != opt.rank) continue;
    fs::path f = caseFolder(rep.folder, c.index);
    if (caseComplete(f)) {
      if (!opt.resume)
        throw InputError(SourceLocation{spec.file.string(), 0, 0}, "directory", f.string(),
                         "a case folder already exists", "--resume to reuse completed cases, or another directory");
      ++rep.reused;
      continue;
    }
    fs::remove_all(f);  // an incomplete folder from an interrupted run
    todo.push_back(&c);
  }

  int workers = spec.parallel > 0 ? spec.parallel : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  workers = std::max(1, std::min<int>(workers, static_cast<int>(todo.size())));
  std::atomic<std::size_t> next{0};
  std::atomic<int> done{0};
  std::mutex mtx;
  Progress progress(fmt::format("sweep {} (rank {}/{})", spec.name, opt.rank, opt.ranks), opt.progress);
  std::vector<std::string> unrecorded;  // failures whose error file could not be written
  auto work = [&] {
    while (!stopRequested()) {
      std::size_t i = next.fetch_add(1);
      if (i >= todo.size()) return;
      const Case& c = *todo[i];
      try {
        Scenario sc = scenario::readText(caseYaml(baseYaml, c), fmt::format("{} case {}", spec.file.string(), c.index));
        sc.name = fmt::format("{}_case_{:04d}", spec.name, c.index);
        RunOptions ro;
        ro.progress = false;
        ro.printWarnings = false;  // each case's warnings are in its summary.json and report
        runScenario(sc, caseFolder(rep.folder, c.index), false, ro);
      } catch (const RunInterrupted&) {
        return;  // Ctrl-C: the case left nothing behind and is run again by --resume
      } catch (const std::exception& e) {
        std::lock_guard<std::mutex> lock(mtx);
        rep.failed.push_back(c.index);
        recordCaseError(rep.folder, c.index, e.what(), unrecorded);
      }
      int d = ++done;
      std::lock_guard<std::mutex> lock(mtx);
      if (!stopRequested()) progress.update(static_cast<double>(d) / todo.size(), fmt::format("{}/{} cases", d, todo.size()));
    }
  };
  std::vector<std::thread> pool;
  for (int w = 1; w < workers; ++w) pool.emplace_back(work);
  work();
  for (auto& t : pool) t.join();
  progress.finish();
  if (!unrecorded.empty())
    throw Error(fmt::format("{} failed case(s) could not be recorded in {}: {}", unrecorded.size(),
                            (rep.folder / "cases").string(), unrecorded.front()));
  if (stopRequested())
    throw RunInterrupted(fmt::format("sweep {}: interrupted by {} after {} of {} cases (each finished case is kept); "
                                     "continue with needlesim sweep {} --resume",
                                     spec.name, stopSignalName(), done.load(),
                                     todo.size(), spec.file.string()),
                         stopSignal());
  rep.ran = static_cast<int>(todo.size()) - static_cast<int>(rep.failed.size());
  std::sort(rep.failed.begin(), rep.failed.end());
  if (opt.rank == 0 && opt.ranks == 1) gatherSweep(spec, cases, rep);
  return rep;
}

namespace {
// The units the study's report shows values in: those its cases' scenario chose
// (output.units of a case's summary.json, all cases share them); SI without one.
units::DisplayUnits caseDisplayUnits(const nlohmann::json& summary) {
  units::DisplayUnits display;
  const nlohmann::json::json_pointer at("/scenario/output/units");
  if (!summary.contains(at) || !summary[at].is_object()) return display;
  for (const auto& [dimension, unit] : summary[at].items())
    if (unit.is_string()) display.set(dimension, unit.get<std::string>());
  return display;
}
}  // namespace

void gatherSweep(const StudySpec& spec, const std::vector<Case>& cases, SweepReport& rep) {
  // Result keys and units from the completed cases, in first-seen order.
  std::vector<std::pair<std::string, std::string>> keys;
  std::map<int, nlohmann::json> results;
  std::vector<int> missing;
  units::DisplayUnits display;
  for (const auto& c : cases) {
    fs::path f = caseFolder(rep.folder, c.index) / "summary.json";
    if (!fs::exists(f)) {
      missing.push_back(c.index);
      continue;
    }
    nlohmann::json s = nlohmann::json::parse(std::ifstream(f));
    for (auto& [k, v] : s["results"].items()) {
      bool seen = false;
      for (const auto& kk : keys) seen = seen || kk.first == k;
      if (!seen) keys.emplace_back(k, v.value("unit", "1"));
    }
    results[c.index] = s["results"];
    if (display.empty()) display = caseDisplayUnits(s);
  }
  std::vector<io::Column> cols{{"case", "1"}, {"complete", "1"}};
  for (std::size_t k = 0; k < spec.parameters.size(); ++k) {
    units::Dim d{};
    for (const auto& c : cases)
      if (std::isfinite(c.values_si[k])) {
        d = units::parse(c.assignments[k].second).dim;
        break;
      }
    cols.push_back({spec.parameters[k].field, units::siName(d)});
  }
  for (const auto& [k, u] : keys) cols.push_back({k, u});
  io::Table table(cols);
  for (const auto& c : cases) {
    std::vector<double> row{static_cast<double>(c.index), results.count(c.index) ? 1.0 : 0.0};
    for (double v : c.values_si) row.push_back(v);
    for (const auto& [k, u] : keys) {
      double v = NAN;
      if (results.count(c.index) && results[c.index].contains(k) && results[c.index][k]["value"].is_number())
        v = results[c.index][k]["value"].get<double>();
      row.push_back(v);
    }
    table.addRow(row);
  }
  io::writeFileAtomic(rep.folder / "study.csv", table.csv());

  nlohmann::json j = {{"name", spec.name},
                      {"study_file", spec.file.string()},
                      {"scenario", spec.scenario_file.string()},
                      {"cases", cases.size()},
                      {"complete", cases.size() - missing.size()},
                      {"rerun", missing}};
  nlohmann::json list = nlohmann::json::array();
  for (const auto& c : cases) {
    nlohmann::json a = nlohmann::json::object();
    for (const auto& [f, v] : c.assignments) a[f] = v;
    list.push_back({{"case", c.index}, {"folder", fmt::format("cases/case_{:04d}", c.index)}, {"set", a}});
  }
  j["case_list"] = list;
  io::writeFileAtomic(rep.folder / "study.json", j.dump(2) + "\n");

  io::HtmlReport html;
  html.title = "needlesim study: " + spec.name;
  html.subtitle = "base scenario " + spec.scenario_file.string();
  html.facts.emplace_back("cases", std::to_string(cases.size()));
  html.facts.emplace_back("complete", std::to_string(cases.size() - missing.size()));
  if (!missing.empty()) {
    std::string m;
    for (int i : missing) m += (m.empty() ? "" : ", ") + std::to_string(i);
    html.facts.emplace_back("to rerun (needlesim sweep --resume)", m);
  }
  for (std::size_t k = 0; k < spec.parameters.size(); ++k) {
    std::vector<double> x = table.column(spec.parameters[k].field);
    for (const auto& [key, unit] : keys) {
      io::Plot p{key + " against " + spec.parameters[k].field, spec.parameters[k].field + " [" + cols[2 + k].unit + "]",
                 key + " [" + unit + "]", {}};
      p.series.push_back({key, x, table.column(key), true, false});
      html.plots.push_back(results::inDisplayUnits(std::move(p), display));
    }
  }
  html.notes.push_back("One point per case; each case's own folder (cases/case_NNNN) has its summary, time series and report.");
  io::writeFileAtomic(rep.folder / "report.html", html.render());
  rep.failed = missing;
}

}  // namespace needlesim::study
