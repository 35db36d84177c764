#include "needlesim/results/results_folder.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <climits>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>

#include "needlesim/core/error.hpp"
#include "needlesim/core/progress.hpp"
#include "needlesim/core/version.hpp"
#include "needlesim/io/atomic_file.hpp"
#include "needlesim/results/display_units.hpp"

namespace needlesim::io {
namespace fs = std::filesystem;

namespace {

// How OpenMP's idle threads waited: the settings libgomp read from the environment (the CLI and
// the Python package set GOMP_SPINCOUNT before libgomp starts, apps/needlesim/openmp_wait.cpp).
// Wall times depend on it.
std::string openMpWait() {
  std::string settings;
  for (const char* name : {"OMP_WAIT_POLICY", "GOMP_SPINCOUNT"})
    if (const char* value = std::getenv(name))
      settings += fmt::format("{}{}={}", settings.empty() ? "" : " ", name, value);
  return settings.empty() ? "libgomp's default (spins ~300000 times, then sleeps)" : settings;
}

nlohmann::json safeNumber(double v) {
  if (std::isfinite(v)) return v;
  return nullptr;  // never write NaN into JSON
}

fs::path parentOf(const fs::path& target) { return target.has_parent_path() ? target.parent_path() : fs::path("."); }

// Whether process `p` still runs: it exists and is not a zombie (a killed
// process stays one until its parent, or init, collects it).
bool processRuns(pid_t p) {
  if (::kill(p, 0) == -1 && errno == ESRCH) return false;
  std::ifstream stat("/proc/" + std::to_string(p) + "/stat");
  std::string line;
  if (!std::getline(stat, line)) return true;  // cannot tell: keep its folder
  const auto close = line.rfind(')');
  return !(close != std::string::npos && close + 2 < line.size() && (line[close + 2] == 'Z' || line[close + 2] == 'X'));
}

// The pid of a staging folder's name ".<name>.partial-<pid>", or 0 for any other name.
pid_t stagePid(const std::string& n) {
  const auto at = n.rfind(".partial-");
  if (n.size() < 2 || n[0] != '.' || at == std::string::npos || at < 2) return 0;
  const std::string pid = n.substr(at + 9);
  if (pid.empty() || pid.size() > 9 || pid.find_first_not_of("0123456789") != std::string::npos) return 0;
  return static_cast<pid_t>(std::stol(pid));
}

InputError badTarget(const fs::path& target, const std::string& field, const std::string& source,
                     const std::string& problem, const std::string& allowed) {
  return InputError(field == "--out" ? commandLine() : SourceLocation{source, 0, 0}, field, target.string(), problem,
                    allowed);
}

// The parent folder exists (created if needed) and a file can be made in it.
void checkParentWritable(const fs::path& target, const std::string& field, const std::string& source) {
  const fs::path parent = parentOf(target);
  std::error_code ec;
  fs::create_directories(parent, ec);
  if (ec)
    throw badTarget(target, field, source, "its folder " + parent.string() + " cannot be created: " + ec.message(),
                    "a path in a folder you can write");
  const fs::path probe = parent / fmt::format(".needlesim-probe-{}", ::getpid());
  const int fd = ::open(probe.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0600);
  if (fd < 0)
    throw badTarget(target, field, source,
                    "its folder " + parent.string() + " is not writable: " + std::strerror(errno),
                    "a path in a folder you can write");
  ::close(fd);
  ::unlink(probe.c_str());
}
}  // namespace

fs::path outputPath(const fs::path& given, const std::string& field, const SourceLocation& where) {
  fs::path p = given.lexically_normal();
  while (!p.empty() && !p.has_filename() && p.has_relative_path()) p = p.parent_path();  // "out/" -> "out"
  const std::string name = p.filename().string();
  if (name.empty() || name == "." || name == "..")
    throw InputError(where, field, given.string(), "names no results folder (it ends in '.', '..' or '/')",
                     "a folder path such as results/run1");
  return p;
}

namespace {
// Whether `file` is a record needlesim wrote: JSON with its version record and a "status".
bool isNeedlesimRecord(const fs::path& file) {
  std::error_code ec;
  if (!fs::is_regular_file(file, ec)) return false;
  try {
    const auto s = nlohmann::json::parse(std::ifstream(file));
    return s.is_object() && s.contains("status") && s.contains("needlesim") && s["needlesim"].is_object() &&
           s["needlesim"].contains("version");
  } catch (const std::exception&) {
    return false;
  }
}
}  // namespace

bool isResultsFolder(const fs::path& dir) {
  return isNeedlesimRecord(dir / "summary.json") || isNeedlesimRecord(dir / "fit.json");
}

std::string describeContents(const fs::path& path) {
  std::error_code ec;
  if (!fs::is_directory(path, ec)) return fs::is_regular_file(path, ec) ? "a file" : "something that is not a folder";
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(path, ec))
    names.push_back(e.path().filename().string() + (e.is_directory() ? "/" : ""));
  if (names.empty()) return "an empty folder";
  std::sort(names.begin(), names.end());
  std::string list;
  for (std::size_t i = 0; i < std::min<std::size_t>(names.size(), 3); ++i) list += (i ? ", " : "") + names[i];
  if (names.size() > 3) list += fmt::format(" and {} more", names.size() - 3);
  return "a folder holding " + list;
}

void checkOutputTarget(const fs::path& target, const std::string& field, const std::string& source,
                       bool overwrite) {
  // The longest name made from the target: its staging folder ".<name>-<n>.partial-<pid>".
  constexpr std::size_t kSuffixes = 25;
  if (target.filename().string().size() + kSuffixes > NAME_MAX)
    throw badTarget(target, field, source,
                    fmt::format("its folder name has {} characters, too long for the file system",
                                target.filename().string().size()),
                    fmt::format("a name of at most {} characters", NAME_MAX - kSuffixes));
  if (fs::absolute(target).string().size() + 64 > PATH_MAX)
    throw badTarget(target, field, source, "is too long for the file system",
                    fmt::format("a path of at most {} characters in all", PATH_MAX - 64));
  std::error_code ec;
  if (overwrite && fs::exists(target, ec) && !isResultsFolder(target))
    throw badTarget(target, field, source,
                    "is " + describeContents(target) + ", not a needlesim results folder; --overwrite will not delete it",
                    "--overwrite replaces only a folder written by needlesim (with its summary.json, or fit.json for a "
                    "fit); choose another path for the results");
  checkParentWritable(target, field, source);
}

int removeStaleStages(const fs::path& parent) {
  int removed = 0;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(parent, ec)) {
    const pid_t p = stagePid(e.path().filename().string());
    if (p <= 0 || p == ::getpid() || !e.is_directory(ec) || e.is_symlink(ec) || processRuns(p)) continue;
    std::error_code rm;
    fs::remove_all(e.path(), rm);
    if (!rm) ++removed;
  }
  return removed;
}

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

fs::path resolveResultsTarget(const fs::path& chosen, const std::string& field, const SourceLocation& where,
                              bool overwrite) {
  checkOutputTarget(chosen, field.empty() ? "name" : field, where.file, overwrite && !field.empty());
  if (field.empty()) return freeResultsPath(chosen);
  if (fs::exists(chosen) && !overwrite)
    throw InputError(where, field, chosen.string(), "results folder already exists",
                     "a new folder, or --overwrite to replace it");
  return chosen;
}

fs::path stagingFolder(const fs::path& target) {
  return target.parent_path() / fmt::format(".{}.partial-{}", target.filename().string(), ::getpid());
}

void checkReplaceable(const fs::path& target, bool replace) {
  std::error_code ec;
  if (fs::exists(target, ec) && !replace)
    throw Error("results folder " + target.string() +
                " already exists; choose another with --out or pass --overwrite to replace it");
  if (fs::exists(target, ec) && !isResultsFolder(target))
    throw Error("cannot replace " + target.string() + ": it is " + describeContents(target) +
                ", not a needlesim results folder");
}

void moveStageIntoPlace(const fs::path& stage, const fs::path& target) {
  if (!fs::exists(target)) {
    fs::rename(stage, target);
    return;
  }
  const fs::path old = parentOf(target) / fmt::format(".{}.old-{}", target.filename().string(), ::getpid());
  fs::rename(target, old);
  fs::rename(stage, target);
  fs::remove_all(old);
}

ResultsFolder::ResultsFolder(const Scenario& scenario, fs::path target, bool printWarnings)
    : scenario_(scenario), target_(outputPath(target, "--out", commandLine())), printWarnings_(printWarnings) {
  stage_ = stagingFolder(target_);
  removeIfStoppedHard(stage_);  // a stop inside a BlockingCall ends the process without unwinding
}

ResultsFolder::~ResultsFolder() {
  forgetOnStop(stage_);
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

void ResultsFolder::warning(const std::string& text) {
  if (printWarnings_) fmt::print(stderr, "{}warning: {}\n", Progress::stderrIsTerminal() ? "\r\033[K" : "", text);
  warnings_.push_back(text);
}

void ResultsFolder::commit(bool replace, double wall_seconds, const std::string& failure) {
  const std::string writing = "writing " + target_.string();
  throwIfStopRequested(writing);  // a stop before the folder is in place commits nothing
  checkReplaceable(target_, replace);
  fs::create_directories(stage_);
  for (auto& f : fields_) f->close();  // the last HDF5 data reaches the disk, or Error
  fields_.clear();
  throwIfStopRequested(writing);
  nlohmann::json files = writeTables();
  throwIfStopRequested(writing);
  for (const auto& f : field_names_) {
    files.push_back(f + ".xdmf");
    files.push_back(f + ".h5");
  }
  if (scenario_.output.html) files.push_back("report.html");
  files.push_back("summary.json");
  writeFileAtomic(stage_ / "summary.json", summaryJson(files, wall_seconds, failure).dump(2) + "\n");
  if (scenario_.output.html) writeFileAtomic(stage_ / "report.html", report(wall_seconds, failure).render());
  throwIfStopRequested(writing);
  moveIntoPlace();
  committed_ = true;
  files_ = files.get<std::vector<std::string>>();
}

void ResultsFolder::moveIntoPlace() { moveStageIntoPlace(stage_, target_); }

nlohmann::json ResultsFolder::writeTables() const {
  nlohmann::json files = nlohmann::json::array();
  if (!scenario_.output.csv) return files;
  for (const auto& [name, t] : tables_) {
    writeFileAtomic(stage_ / (name + ".csv"), t.csv());
    files.push_back(name + ".csv");
  }
  return files;
}

nlohmann::json ResultsFolder::summaryJson(const nlohmann::json& files, double wall_seconds,
                                          const std::string& failure) const {
  nlohmann::json res = nlohmann::json::object();
  for (const auto& r : results_)
    res[r.key] = {{"value", safeNumber(r.value)}, {"unit", r.unit}, {"meaning", r.meaning}};
  return {{"needlesim", {{"version", kVersion}, {"git_revision", kGitRevision}, {"openmp_wait", openMpWait()}}},
          {"engine", scenario_.model.engine},
          {"status", failure.empty() ? "complete" : "stopped"},
          {"stopped_because", failure.empty() ? nlohmann::json(nullptr) : nlohmann::json(failure)},
          {"wall_time", {{"value", wall_seconds}, {"unit", "s"}}},
          {"results", res},
          {"warnings", warnings_},
          {"notes", notes_},
          {"files", files},
          {"scenario_source", scenario_.source},
          {"scenario", scenarioToJson(scenario_)}};
}

HtmlReport ResultsFolder::report(double wall_seconds, const std::string& failure) const {
  HtmlReport rep;
  rep.title = "needlesim: " + scenario_.name;
  rep.subtitle = scenario_.description.empty() ? scenario_.source : scenario_.description;
  rep.facts.emplace_back("engine", scenario_.model.engine);
  rep.facts.emplace_back("scenario", scenario_.source);
  if (!failure.empty()) rep.facts.emplace_back("STOPPED", failure);
  for (const auto& r : results_)
    rep.facts.emplace_back(r.key + " (" + r.meaning + ")", results::shownText(r.value, r.unit, scenario_.output.units));
  rep.facts.emplace_back("wall time", fmt::format("{:.3f} s", wall_seconds));
  for (const auto& p : plots_) rep.plots.push_back(results::inDisplayUnits(p, scenario_.output.units));
  rep.warnings = warnings_;
  rep.notes = notes_;
  return rep;
}


}  // namespace needlesim::io
