#include "needlesim/live/step_log.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "needlesim/api/scenario_impl.hpp"
#include "needlesim/core/error.hpp"
#include "needlesim/io/csv_reader.hpp"
#include "needlesim/results/results_folder.hpp"
#include "needlesim/results/forces_table.hpp"

namespace needlesim::live {

namespace fs = std::filesystem;

int phaseIndex(const std::string& phase) {
  for (int i = 0; i < 5; ++i)
    if (phase == kPhases[i]) return i;
  return -1;
}

io::Table StepLog::commandsTable() const {
  io::Table t({{"time", "s"}, {"dt", "s"}, {"depth", "m"}, {"lateral", "m"}, {"rotation", "rad"}, {"tilt", "rad"},
               {"roll", "rad"}, {"reset", "1"}});
  t.exact();  // a replay steps the very doubles the session stepped
  t.reserve(rows_.size());
  for (const StepRecord& r : rows_)
    t.addRow({r.time, r.dt, r.pose.depth, r.pose.lateral, r.pose.rotation, r.pose.tilt, r.pose.roll, r.reset ? 1.0 : 0.0});
  return t;
}

io::Table StepLog::forcesTable(bool flexible) const {
  results::ForcesTable t(flexible, {{"force_stiffness", "N"}, {"force_cutting", "N"}, {"force_friction", "N"}, {"phase", "1"}});
  t.reserve(rows_.size());
  double previous = 0.0;
  for (const StepRecord& r : rows_) {
    const api::State& s = r.state;
    if (r.reset) previous = 0.0;  // the session starts over at depth 0
    results::NeedleForces f;
    f.time = r.time;
    f.depth = s.depth;
    f.velocity = (r.pose.depth - previous) / r.dt;
    f.force_total = s.axial_force;
    f.force_lateral = s.lateral_force;
    f.tip_x = s.tip_x;
    f.tip_y = s.tip_y;
    f.tip_deflection = s.tip_deflection;
    previous = r.pose.depth;
    t.add(f, {s.stiffness_force, s.cutting_force, s.friction_force, static_cast<double>(phaseIndex(s.phase))});
  }
  return t.release();
}

namespace {

io::Plot forceDepthPlot(const io::Table& forces) {
  io::Plot p{"Axial force against depth (live session)", "depth [mm]", "force [N]", {}};
  io::PlotSeries total{"axial force", {}, {}}, friction{"friction", {}, {}};
  const std::size_t step = std::max<std::size_t>(1, forces.rows() / 4000);  // a readable report
  const auto depth = forces.column("depth"), axial = forces.column("force_total"), fr = forces.column("force_friction");
  for (std::size_t r = 0; r < forces.rows(); r += step) {
    total.x.push_back(1e3 * depth[r]);
    total.y.push_back(axial[r]);
    friction.x.push_back(1e3 * depth[r]);
    friction.y.push_back(fr[r]);
  }
  p.series = {std::move(total), std::move(friction)};
  return p;
}

void keyResults(io::ResultsFolder& folder, const StepLog& log) {
  double peak = 0.0, deepest = 0.0, punctureDepth = NAN;
  for (const StepRecord& r : log.rows()) {
    peak = std::max(peak, r.state.axial_force);
    deepest = std::max(deepest, r.state.depth);
    if (std::isnan(punctureDepth) && phaseIndex(r.state.phase) >= 2) punctureDepth = r.state.depth;
  }
  folder.result("peak_force", peak, "N", "largest axial force of the session");
  folder.result("max_depth", deepest, "m", "deepest tip position");
  if (!std::isnan(punctureDepth)) folder.result("puncture_depth", punctureDepth, "m", "tip depth at the first puncture");
  folder.result("steps", static_cast<double>(log.size()), "1", "physics steps recorded");
  const auto resets = std::count_if(log.rows().begin(), log.rows().end(), [](const StepRecord& r) { return r.reset; });
  folder.result("resets", static_cast<double>(resets), "1", "resets of the session between recorded steps");
}

}  // namespace

void writeRecording(const api::Scenario& scenario, const StepLog& log, const fs::path& target, bool replace,
                    double wallSeconds, const std::string& origin) {
  const needlesim::Scenario& typed = api::detail::ScenarioAccess::typed(scenario);
  io::ResultsFolder folder(typed, target);
  io::Table forces = log.forcesTable(scenario.engine() != "lumped");
  if (forces.rows() > 0) folder.plot(forceDepthPlot(forces));
  keyResults(folder, log);
  folder.note(origin);
  folder.table("forces", std::move(forces));
  folder.table("commands", log.commandsTable());
  folder.commit(replace, wallSeconds);
}

namespace {

// commands.csv's reset column (recordings without one have no resets): 0 or 1 per row.
std::vector<bool> resetColumn(const io::CsvData& commands) {
  std::vector<bool> resets(commands.rows(), false);
  const int c = commands.find({"reset"});
  if (c < 0) return resets;
  commands.checkDim(c, units::dim::None, "reset");
  for (std::size_t r = 0; r < commands.rows(); ++r) {
    const double v = commands.col(c)[r];
    if (v != 0.0 && v != 1.0)
      throw InputError(SourceLocation{commands.file, commands.lines[r], 0}, "reset", fmt::format("{}", v),
                       "is not a reset flag", "0, or 1 on the first step after a reset");
    resets[r] = v == 1.0;
  }
  return resets;
}

// A recorded row as a step: InputError naming commands.csv's line for a value that no live
// session steps (dt outside (0, 0.1] s, a value that is not finite).
void checkRow(const io::CsvData& commands, std::size_t r, double dt, const Pose& pose) {
  const SourceLocation where{commands.file, commands.lines[r], 0};
  if (!(dt > 0.0 && dt <= 0.1))
    throw InputError(where, "dt", fmt::format("{}", dt), "is not a physics step of a live session", "0 < dt <= 0.1 s");
  const std::pair<const char*, double> values[] = {
      {"depth", pose.depth}, {"lateral", pose.lateral}, {"rotation", pose.rotation}, {"tilt", pose.tilt}, {"roll", pose.roll}};
  for (const auto& [name, value] : values)
    if (!std::isfinite(value)) throw InputError(where, name, fmt::format("{}", value), "is not a finite number", "a finite number");
}

// One replayed step; the session's refusal of a command names the recording's line.
const api::State& stepRow(api::Session& session, const io::CsvData& commands, std::size_t r, double dt, const Pose& pose) {
  checkRow(commands, r, dt, pose);
  try {
    return session.step(commandFor(pose), dt);
  } catch (const api::InputError& e) {
    throw InputError(SourceLocation{commands.file, commands.lines[r], 0}, "command", "", e.what(),
                     "the commands a live session of this scenario steps");
  }
}

}  // namespace

StepLog replay(const fs::path& recording, api::Scenario& scenarioOut) {
  scenarioOut = api::Scenario::fromFile(recording / "summary.json");
  const io::CsvData commands = io::readCsv(recording / "commands.csv");
  const auto col = [&](const char* name, units::Dim dim) { return commands.col(commands.require({name}, dim, name)); };
  const auto& dt = col("dt", units::dim::Time);
  const auto& depth = col("depth", units::dim::Length);
  const auto& lateral = col("lateral", units::dim::Length);
  const auto& rotation = col("rotation", units::dim::Angle);
  const auto& tilt = col("tilt", units::dim::Angle);
  const auto& roll = col("roll", units::dim::Angle);
  const std::vector<bool> resets = resetColumn(commands);
  api::Session session(scenarioOut);
  StepLog log;
  log.reserve(commands.rows());
  for (std::size_t r = 0; r < commands.rows(); ++r) {
    if (resets[r]) {
      session.reset();
      log.markReset();
    }
    const Pose pose{depth[r], lateral[r], rotation[r], tilt[r], roll[r]};
    log.add(dt[r], pose, stepRow(session, commands, r, dt[r], pose));
  }
  return log;
}

double largestDifference(const io::Table& replayed, const fs::path& recordedForces) {
  const io::CsvData recorded = io::readCsv(recordedForces);
  if (recorded.rows() != replayed.rows()) return INFINITY;
  double worst = 0.0;
  for (const char* name : {"depth", "force_total", "force_lateral", "tip_x", "tip_y", "force_friction"}) {
    const int c = recorded.find({name});
    if (c < 0) return INFINITY;
    const std::vector<double>& old = recorded.col(c);
    const std::size_t n = replayed.columnIndex(name);
    for (std::size_t r = 0; r < old.size(); ++r) worst = std::max(worst, std::abs(replayed.at(r, n) - old[r]));
  }
  return worst;
}

}  // namespace needlesim::live
