// api::run and api::Results: any engine, in memory or into a results folder.
#include <algorithm>
#include <fstream>

#include <nlohmann/json.hpp>

#include "needlesim/api/scenario_impl.hpp"
#include "needlesim/api/translate.hpp"
#include "needlesim/engines/memory_sink.hpp"
#include "needlesim/engines/run_scenario.hpp"

namespace needlesim::api {

namespace {

// "a, b and c" for error messages.
template <class Map>
std::string namesOf(const Map& m) {
  std::string s;
  std::size_t i = 0;
  for (const auto& [name, _] : m) {
    s += (i == 0 ? "" : i + 1 == m.size() ? " or " : ", ") + name;
    ++i;
  }
  return s.empty() ? "(none)" : s;
}

Table publicTable(const io::Table& t) {
  Table out;
  for (const auto& c : t.columns()) {
    out.names.push_back(c.name);
    out.units.push_back(c.unit);
    out.columns.push_back(t.column(c.name));
  }
  return out;
}

std::size_t columnIndex(const Table& t, const std::string& name) {
  const auto it = std::find(t.names.begin(), t.names.end(), name);
  if (it == t.names.end()) {
    std::map<std::string, int> names;
    for (const auto& n : t.names) names[n] = 0;
    detail::argumentError("Table::column", "name", name, "is not a column of this table", namesOf(names));
  }
  return static_cast<std::size_t>(it - t.names.begin());
}

// Status, notes and warnings of a committed results folder (its summary.json).
void readSummary(Results& r) {
  std::ifstream in(r.folder / "summary.json");
  const nlohmann::json s = nlohmann::json::parse(in, nullptr, false);
  if (!s.is_object()) throw Error("cannot read " + (r.folder / "summary.json").string());
  r.status = s.value("status", "");
  r.notes = s.value("notes", std::vector<std::string>{});
  r.warnings = s.value("warnings", std::vector<std::string>{});
}

std::vector<std::filesystem::path> fieldFilesIn(const std::filesystem::path& folder) {
  std::vector<std::filesystem::path> files;
  for (const auto& e : std::filesystem::directory_iterator(folder))
    if (e.is_regular_file() && e.path().extension() == ".xdmf") files.push_back(e.path());
  std::sort(files.begin(), files.end());
  return files;
}

}  // namespace

const std::vector<double>& Table::column(const std::string& name) const { return columns[columnIndex(*this, name)]; }
const std::string& Table::unit(const std::string& name) const { return units[columnIndex(*this, name)]; }

const Value& Results::value(const std::string& name) const {
  const auto it = values.find(name);
  if (it == values.end()) detail::argumentError("Results::value", "name", name, "is not a key result of this run", namesOf(values));
  return it->second;
}

const Table& Results::table(const std::string& name) const {
  const auto it = tables.find(name);
  if (it == tables.end()) detail::argumentError("Results::table", "name", name, "is not a table of this run", namesOf(tables));
  return it->second;
}

Results detail::memoryResults(MemorySink& sink) {
  Results r;
  r.status = "complete";
  for (const auto& [key, v] : sink.results) r.values[key] = Value{v.value, v.unit, v.meaning};
  for (const auto& [name, t] : sink.tables) r.tables[name] = publicTable(t);
  r.notes = std::move(sink.notes);
  r.warnings = std::move(sink.warnings);
  return r;
}

void detail::readFolder(Results& r) {
  readSummary(r);
  r.fieldFiles = fieldFilesIn(r.folder);
}

Results run(const Scenario& scenario) {
  return detail::translated([&] {
    MemorySink sink = runInMemory(detail::ScenarioAccess::typed(scenario));
    return detail::memoryResults(sink);
  });
}

Results run(const Scenario& scenario, const std::filesystem::path& folder, const RunSettings& settings) {
  return detail::translated([&] {
    RunOptions options;
    options.progress = settings.progress;
    options.printWarnings = settings.printWarnings;
    RunOutcome o = runScenario(detail::ScenarioAccess::typed(scenario), folder, settings.overwrite, options);
    Results r;
    r.folder = o.folder;
    for (const auto& k : o.results) r.values[k.key] = Value{k.value, k.unit, k.meaning};
    for (const auto& [name, t] : o.tables) r.tables[name] = publicTable(t);
    readSummary(r);
    r.fieldFiles = fieldFilesIn(r.folder);
    return r;
  });
}

}  // namespace needlesim::api
