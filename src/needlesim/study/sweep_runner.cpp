#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <atomic>
#include <cmath>
#include <fstream>
#include <map>
#include <memory>
#include <mutex>
#include <regex>
#include <sstream>
#include <thread>

#include "needlesim/core/error.hpp"
#include "needlesim/core/progress.hpp"
#include "needlesim/core/version.hpp"
#include "needlesim/engines/run_scenario.hpp"
#include "needlesim/io/atomic_file.hpp"
#include "needlesim/io/folder_lock.hpp"
#include "needlesim/results/results_folder.hpp"
#include "needlesim/io/table.hpp"
#include "needlesim/results/display_units.hpp"
#include "needlesim/scenario/reader.hpp"
#include "needlesim/study/study.hpp"
#include "needlesim/study/study_report.hpp"

namespace needlesim::study {
namespace fs = std::filesystem;

namespace {

std::string readText(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// The study folder and which input named it: --out, the study file's directory, or its name.
struct StudyTarget {
  fs::path path;
  std::string field;
  SourceLocation where;
};

StudyTarget chooseStudyFolder(const StudySpec& spec, const SweepOptions& opt) {
  const SourceLocation inFile{spec.file.string(), 0, 0};
  if (!opt.out.empty()) return {io::outputPath(opt.out, "--out", commandLine()), "--out", commandLine()};
  if (!spec.directory.empty()) return {io::outputPath(spec.directory, "directory", inFile), "directory", inFile};
  return {fs::path("results") / spec.name, "name", inFile};
}

// The checked study folder, locked for this process (FolderLock): free, or an
// earlier study's folder to resume in or (with --overwrite) to clear; anything
// else there is refused.
fs::path prepareStudyFolder(const StudySpec& spec, const SweepOptions& opt, std::unique_ptr<io::FolderLock>& lock) {
  const StudyTarget t = chooseStudyFolder(spec, opt);
  if (opt.resume && opt.overwrite)
    throw InputError(commandLine(), "--overwrite", "", "cannot go with --resume",
                     "--resume to reuse the completed cases, or --overwrite to replace the study");
  io::checkOutputTarget(t.path, t.field, t.where.file, false);
  lock = std::make_unique<io::FolderLock>(t.path, t.field, t.where,
                                          opt.ranks > 1 ? io::FolderLock::Mode::Shared : io::FolderLock::Mode::Exclusive);
  if (!fs::exists(t.path)) return t.path;
  if (!isStudyFolder(t.path))
    throw InputError(t.where, t.field, t.path.string(),
                     "is " + io::describeContents(t.path) + ", not a needlesim study folder; nothing is written there",
                     "a new folder, or the folder of an earlier run of this study (with --resume or --overwrite)");
  if (opt.resume) return t.path;
  if (!opt.overwrite)
    throw InputError(t.where, t.field, t.path.string(), "the study folder already exists",
                     "--resume to reuse its completed cases, --overwrite to replace it, or another folder (--out)");
  return t.path;
}

// Names in cases/: case_NNNN, case_NNNN.error.txt and the staging, replaced and temporary names made from them.
bool isCaseEntry(const std::string& name) {
  static const std::regex pattern(
      R"(\.?case_[0-9]+(\.error\.txt(\.tmp\.[0-9]+)?|\.partial-[0-9]+|\.old-[0-9]+|\.kept-[0-9]+)?)");
  return std::regex_match(name, pattern);
}

// Names in a study folder: cases/, study.csv, study.json, report.html, and their temporary names.
bool isStudyEntry(const std::string& name) {
  static const std::regex pattern(R"((cases|(study\.csv|study\.json|report\.html)(\.tmp\.[0-9]+)?))");
  return std::regex_match(name, pattern);
}

fs::path caseFolder(const fs::path& study, int index) { return study / "cases" / fmt::format("case_{:04d}", index); }

// A case folder a run committed: its summary.json is a complete needlesim record.
bool caseComplete(const fs::path& folder) { return io::isResultsFolder(folder); }

fs::path errorFileOf(const fs::path& study, int index) {
  return study / "cases" / fmt::format("case_{:04d}.error.txt", index);
}

// A path for messages, relative to the study folder ("cases/case_0001").
std::string shown(const fs::path& p, const fs::path& study) { return p.lexically_relative(study).string(); }

// What a sweep says about folders it leaves or sets aside: on the terminal at once, and in the report.
void say(SweepReport& rep, const std::string& text) {
  fmt::print(stderr, "note: {}\n", text);
  rep.notes.push_back(text);
}

// Moves a case folder whose contents needlesim cannot vouch for out of the case's way,
// to the first free case_NNNN.kept-K beside it: nothing in it is deleted.
fs::path setAside(const fs::path& folder) {
  for (int k = 1; k < 100000; ++k) {
    fs::path kept = folder;
    kept += fmt::format(".kept-{}", k);
    if (!fs::exists(kept) && !fs::is_symlink(kept)) {
      fs::rename(folder, kept);
      return kept;
    }
  }
  throw Error("no free name to keep " + folder.string() + " under");
}

// The files a committed case folder's summary.json lists as written (plain names in the
// folder, summary.json last): what --overwrite may delete.
std::vector<fs::path> filesWritten(const fs::path& folder) {
  std::vector<fs::path> files;
  try {
    const auto summary = nlohmann::json::parse(std::ifstream(folder / "summary.json"));
    if (summary.contains("files") && summary["files"].is_array())
      for (const auto& f : summary["files"]) {
        if (!f.is_string()) continue;
        const fs::path name = f.get<std::string>();
        if (name.has_filename() && name == name.filename() && name != "." && name != ".." && name != "summary.json")
          files.push_back(folder / name);
      }
  } catch (const nlohmann::json::exception&) {
    return {};  // checked by caseComplete before; changed since: nothing is known to be ours
  }
  files.push_back(folder / "summary.json");
  return files;
}

// --overwrite on one case folder: deletes the files its run wrote; a folder left holding
// anything else is set aside (case_NNNN.kept-K) and named.
void clearCase(const fs::path& folder, const fs::path& study, SweepReport& rep) {
  if (caseComplete(folder))
    for (const auto& f : filesWritten(folder))
      if (fs::is_regular_file(fs::symlink_status(f))) fs::remove(f);
  if (fs::is_empty(folder)) {
    fs::remove(folder);
    return;
  }
  const std::string left = io::describeContents(folder);
  const fs::path kept = setAside(folder);
  say(rep, fmt::format("{} held what needlesim did not write ({}); it is kept, unchanged, as {}", shown(folder, study),
                       left.substr(left.find("holding") == std::string::npos ? 0 : left.find("holding") + 8),
                       shown(kept, study)));
}

// --overwrite: removes what an earlier run of the study wrote (study.csv, study.json,
// report.html, the case folders' own files, error files, staging folders of dead
// processes) and nothing else; what is left is named.
void clearStudyFolder(const fs::path& study, SweepReport& rep) {
  static const std::regex ownFile(R"((study\.csv|study\.json|report\.html)(\.tmp\.[0-9]+)?)");
  static const std::regex ownCaseFile(R"(case_[0-9]+\.error\.txt(\.tmp\.[0-9]+)?)");
  static const std::regex caseDir(R"(case_[0-9]+)");
  for (const auto& e : fs::directory_iterator(study))
    if (std::regex_match(e.path().filename().string(), ownFile) && e.is_regular_file() && !e.is_symlink())
      fs::remove(e.path());
  const fs::path cases = study / "cases";
  if (!fs::exists(cases)) return;
  io::removeStaleStages(cases);
  std::vector<fs::path> entries;
  for (const auto& e : fs::directory_iterator(cases)) entries.push_back(e.path());
  std::sort(entries.begin(), entries.end());
  for (const auto& p : entries) {
    const std::string name = p.filename().string();
    const auto status = fs::symlink_status(p);
    if (std::regex_match(name, ownCaseFile) && fs::is_regular_file(status))
      fs::remove(p);
    else if (std::regex_match(name, caseDir) && fs::is_directory(status))
      clearCase(p, study, rep);
    else if (fs::exists(status))
      say(rep, fmt::format("{} is left as it is (--overwrite deletes only what needlesim wrote)", shown(p, study)));
  }
}

// A case to run whose folder exists but holds no complete run (a damaged or truncated
// summary.json, a folder someone made): set aside, nothing deleted, and said.
void setAsideIncompleteCase(const fs::path& folder, const fs::path& study, SweepReport& rep) {
  const bool hasSummary = fs::exists(fs::symlink_status(folder / "summary.json"));
  const fs::path kept = setAside(folder);
  say(rep, fmt::format("{}: {}; the case runs again and the folder is kept, unchanged, as {}", shown(folder, study),
                       hasSummary ? "its summary.json cannot be read (damaged or cut short)" : "it holds no summary.json",
                       shown(kept, study)));
}

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

bool isStudyFolder(const fs::path& dir) {
  std::error_code ec;
  if (!fs::is_directory(dir, ec) || fs::is_symlink(dir, ec)) return false;
  for (const auto& e : fs::directory_iterator(dir, ec)) {
    const std::string name = e.path().filename().string();
    if (!isStudyEntry(name)) return false;
    if (name != "cases") continue;
    if (!e.is_directory() || e.is_symlink()) return false;
    for (const auto& c : fs::directory_iterator(e.path(), ec))
      if (!isCaseEntry(c.path().filename().string())) return false;
  }
  return !ec;
}

namespace {

// This rank's cases to run; completed ones are reused on --resume, an incomplete folder is set aside.
std::vector<const Case*> casesToRun(const std::vector<Case>& cases, const SweepOptions& opt, SweepReport& rep) {
  std::vector<const Case*> todo;
  for (const auto& c : cases) {
    if ((c.index - 1) % opt.ranks != opt.rank) continue;
    const fs::path f = caseFolder(rep.folder, c.index);
    const fs::path err = errorFileOf(rep.folder, c.index);
    if (fs::is_regular_file(fs::symlink_status(err))) fs::remove(err);  // the case is complete or runs again
    if (caseComplete(f)) {  // only in a study folder that --resume reuses (prepareStudyFolder)
      ++rep.reused;
      continue;
    }
    if (fs::exists(fs::symlink_status(f))) setAsideIncompleteCase(f, rep.folder, rep);
    todo.push_back(&c);
  }
  return todo;
}

SweepReport runSweepLocked(const StudySpec& spec, const SweepOptions& opt, const std::vector<Case>& cases,
                           const std::string& baseYaml, SweepReport rep);

}  // namespace

SweepReport runSweep(const StudySpec& spec, const SweepOptions& opt) {
  std::string baseYaml = readText(spec.scenario_file);
  std::vector<Case> cases = expandCases(spec, baseYaml);
  SweepReport rep;
  std::unique_ptr<io::FolderLock> lock;  // held until the study is gathered
  rep.folder = prepareStudyFolder(spec, opt, lock);
  rep.cases = static_cast<int>(cases.size());
  const fs::path folder = rep.folder;
  try {
    if (opt.overwrite && fs::exists(rep.folder)) clearStudyFolder(rep.folder, rep);
    fs::create_directories(rep.folder / "cases");
    if (opt.ranks == 1) io::removeStaleStages(rep.folder / "cases");
    return runSweepLocked(spec, opt, cases, baseYaml, std::move(rep));
  } catch (const fs::filesystem_error& e) {
    throw Error(fmt::format("study folder {}: {} ({}); the cases completed so far are kept", folder.string(),
                            e.code().message(), e.path1().string()));
  } catch (const nlohmann::json::exception& e) {
    throw Error(fmt::format("study folder {}: a case's summary.json cannot be read ({})", folder.string(),
                            e.what()));
  }
}

namespace {

SweepReport runSweepLocked(const StudySpec& spec, const SweepOptions& opt, const std::vector<Case>& cases,
                           const std::string& baseYaml, SweepReport rep) {
  const std::vector<const Case*> todo = casesToRun(cases, opt, rep);

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
        throwIfStopRequested("case " + std::to_string(c.index));
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

// Result keys and units of the completed cases, in first-seen order, each case's results
// and the units the cases show values in.
struct CaseResults {
  std::vector<std::pair<std::string, std::string>> keys;
  std::map<int, nlohmann::json> results;
  std::vector<int> missing;
  units::DisplayUnits display;
};

// The units a study's report shows values in: those its cases' scenario chose
// (output.units of a case's summary.json; all cases share them); SI without one.
units::DisplayUnits caseDisplayUnits(const nlohmann::json& summary) {
  units::DisplayUnits display;
  const nlohmann::json::json_pointer at("/scenario/output/units");
  if (!summary.contains(at) || !summary[at].is_object()) return display;
  for (const auto& [dimension, unit] : summary[at].items())
    if (unit.is_string()) display.set(dimension, unit.get<std::string>());
  return display;
}

CaseResults readCaseResults(const std::vector<Case>& cases, const fs::path& folder) {
  CaseResults r;
  for (const auto& c : cases) {
    const fs::path folder_c = caseFolder(folder, c.index);
    nlohmann::json s;
    if (caseComplete(folder_c)) s = nlohmann::json::parse(std::ifstream(folder_c / "summary.json"), nullptr, false);
    if (!s.is_object() || !s.contains("results") || !s["results"].is_object()) {
      r.missing.push_back(c.index);  // not run, failed, or changed since it was checked
      continue;
    }
    for (auto& [k, v] : s["results"].items()) {
      bool seen = false;
      for (const auto& kk : r.keys) seen = seen || kk.first == k;
      if (!seen) r.keys.emplace_back(k, v.is_object() && v.contains("unit") && v["unit"].is_string()
                                            ? v["unit"].get<std::string>() : "1");
    }
    r.results[c.index] = s["results"];
    if (r.display.empty()) r.display = caseDisplayUnits(s);
  }
  return r;
}

// study.csv: case, complete, the inputs (in the study file's order), the outputs.
io::Table studyTable(const StudySpec& spec, const std::vector<Case>& cases, CaseResults& found) {
  std::vector<io::Column> cols{{"case", "1"}, {"complete", "1"}};
  for (std::size_t k = 0; k < spec.parameters.size(); ++k) {
    units::Dim d{};
    for (const auto& c : cases)
      if (std::isfinite(c.values_si[k])) {
        d = units::parse(c.assignments[k].second).dim;
        break;
      }
    cols.push_back({inputColumnName(spec.parameters[k].field), units::siName(d)});
  }
  for (const auto& [k, u] : found.keys) cols.push_back({k, u});
  io::Table table(cols);
  for (const auto& c : cases) {
    std::vector<double> row{static_cast<double>(c.index), found.results.count(c.index) ? 1.0 : 0.0};
    for (double v : c.values_si) row.push_back(v);
    for (const auto& [k, u] : found.keys) {
      double v = NAN;
      if (found.results.count(c.index) && found.results[c.index].contains(k) &&
          found.results[c.index][k].is_object() && found.results[c.index][k].contains("value") &&
          found.results[c.index][k]["value"].is_number())
        v = found.results[c.index][k]["value"].get<double>();
      row.push_back(v);
    }
    table.addRow(row);
  }
  return table;
}

// study.json: the study, its inputs and outputs (the constant ones with their value) and every case's assignments.
nlohmann::json studyJson(const StudyResults& r, const std::vector<int>& missing) {
  const OutputColumns outputs = splitOutputs(r);
  const auto& cols = r.table.columns();
  nlohmann::json inputs = nlohmann::json::array(), varying = nlohmann::json::array(),
                 constant = nlohmann::json::object();
  for (const auto& p : r.spec.parameters) inputs.push_back(p.field);
  for (std::size_t c : outputs.varying) varying.push_back(cols[c].name);
  for (std::size_t c : outputs.constant) {
    std::size_t row = 0;
    while (r.table.at(row, 1) != 1.0) ++row;  // the first complete case
    constant[cols[c].name] = {{"value", r.table.at(row, c)}, {"unit", cols[c].unit}};
  }
  nlohmann::json j = {{"needlesim", {{"version", kVersion}, {"git_revision", kGitRevision}}},
                      {"name", r.spec.name},
                      {"study_file", r.spec.file.string()},
                      {"scenario", r.spec.scenario_file.string()},
                      {"cases", r.cases.size()},
                      {"complete", r.cases.size() - missing.size()},
                      {"rerun", missing},
                      {"inputs", inputs},
                      {"outputs", varying},
                      {"constant_outputs", constant}};
  nlohmann::json list = nlohmann::json::array();
  for (const auto& c : r.cases) {
    nlohmann::json a = nlohmann::json::object();
    for (const auto& [f, v] : c.assignments) a[f] = v;
    list.push_back({{"case", c.index}, {"folder", fmt::format("cases/case_{:04d}", c.index)}, {"set", a}});
  }
  j["case_list"] = list;
  return j;
}

}  // namespace

void gatherSweep(const StudySpec& spec, const std::vector<Case>& cases, SweepReport& rep) {
  CaseResults found = readCaseResults(cases, rep.folder);
  const StudyResults results{spec, cases, studyTable(spec, cases, found), found.display};
  io::writeFileAtomic(rep.folder / "study.csv", results.table.csv());
  io::writeFileAtomic(rep.folder / "study.json", studyJson(results, found.missing).dump(2) + "\n");
  io::writeFileAtomic(rep.folder / "report.html", studyReport(results, found.missing).render());
  rep.overview = studyOverview(results);
  rep.failed = found.missing;
}

}  // namespace needlesim::study
