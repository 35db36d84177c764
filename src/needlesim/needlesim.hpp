#pragma once
// needlesim's public C++ API: read a scenario, run any engine in memory or into a
// results folder, step the real-time models in a control loop, fit material laws
// to data and run parameter studies. Everything is in SI units (m, s, N, Pa, rad).
// This is the one installed header; it needs only the C++20 standard library.
// Link the target needlesim::needlesim (find_package(needlesim)); see docs/api.md.
#include <cstddef>
#include <filesystem>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#if defined(__GNUC__)
#define NEEDLESIM_API __attribute__((visibility("default")))
#else
#define NEEDLESIM_API
#endif

namespace needlesim::api {

// ---------------------------------------------------------------- errors
// Every error needlesim reports is an api::Error; its what() is the message the needlesim
// program prints (for input: file:line:col, the field, the value and what is allowed).
class NEEDLESIM_API Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// A problem with an input: a scenario, a data file or an argument of a call.
class NEEDLESIM_API InputError : public Error {
 public:
  InputError(const std::string& message, std::string file, int line, std::string field);
  const std::string& file() const { return file_; }   // or the source: "<yaml>", "<C++ API>"
  int line() const { return line_; }                 // 1-based; 0 = unknown
  const std::string& field() const { return field_; } // the field or argument at fault
 private:
  std::string file_;
  int line_;
  std::string field_;
};

// A solver that cannot go on (unstable step, divergence); says why and what to change.
class NEEDLESIM_API SolverError : public Error {
 public:
  using Error::Error;
};

// A run stopped by a stop request (SIGINT, SIGTERM).
class NEEDLESIM_API Interrupted : public Error {
 public:
  using Error::Error;
};

// The library's version, e.g. "0.1.0".
NEEDLESIM_API std::string version();

// ---------------------------------------------------------------- scenarios
namespace detail {
struct ScenarioAccess;  // the library's own access to a Scenario's contents
}

// A validated scenario (docs/scenario-format.md). Cheap to copy; immutable.
class NEEDLESIM_API Scenario {
 public:
  // Reads and validates a scenario file (YAML or JSON). InputError names file, line, field.
  static Scenario fromFile(const std::filesystem::path& path);
  // Validates scenario YAML text; `source` names it in error messages.
  static Scenario fromYaml(const std::string& yaml, const std::string& source = "<yaml>");
  // The built-in example scenario (what `needlesim run` uses without a file).
  static Scenario builtIn();

  // A copy with fields set: field path -> value text with its unit, e.g.
  // {"insertion.profile[0].insert.speed", "5 mm/s"}, {"tissue.friction.C_p", "3 N/m"}.
  // Field paths are those of a study (docs/studies.md). InputError for a bad path or value.
  Scenario with(const std::map<std::string, std::string>& values) const;
  Scenario with(const std::string& fieldPath, const std::string& value) const;

  std::string name() const;
  std::string engine() const;    // model.engine: lumped, realtime2d, explicit, mpm, ...
  double duration() const;       // s, the insertion profile's total time
  const std::string& yaml() const;  // the YAML text it was read from

 private:
  struct Impl;
  friend struct detail::ScenarioAccess;
  explicit Scenario(std::shared_ptr<const Impl> impl);
  std::shared_ptr<const Impl> impl_;
};

// ---------------------------------------------------------------- results
struct NEEDLESIM_API Value {
  double value = 0.0;
  std::string unit;     // SI unit text, "1" for dimensionless
  std::string meaning;  // one line for a reader
};

// A time series or other table: named columns with units, the data column by column.
struct NEEDLESIM_API Table {
  std::vector<std::string> names;
  std::vector<std::string> units;
  std::vector<std::vector<double>> columns;  // columns[i] holds names[i]'s values

  std::size_t rows() const { return columns.empty() ? 0 : columns.front().size(); }
  // The column called `name`; InputError listing the column names when there is none.
  const std::vector<double>& column(const std::string& name) const;
  const std::string& unit(const std::string& name) const;
};

struct NEEDLESIM_API Results {
  std::string status;                     // "complete"
  std::map<std::string, Value> values;    // key results (peak force, exit force, ...)
  std::map<std::string, Table> tables;    // "forces" and the engine's other tables
  std::vector<std::string> notes;
  std::vector<std::string> warnings;      // results that may not mean what they seem
  std::filesystem::path folder;           // the results folder ("" for an in-memory run)
  std::vector<std::filesystem::path> fieldFiles;  // the .xdmf field series written (ParaView)

  // The key result / table called `name`; InputError listing the names there are.
  const Value& value(const std::string& name) const;
  const Table& table(const std::string& name) const;
};

// Runs the scenario's engine in memory (no files).
// Throws InputError (engine not in this build, feature it does not model), SolverError.
NEEDLESIM_API Results run(const Scenario& scenario);

struct RunSettings {
  bool overwrite = false;      // replace an existing needlesim results folder
  bool progress = false;       // progress bar on the terminal
  bool printWarnings = false;  // print each warning on stderr as it is raised
};
// Runs into a results folder (summary.json, CSV tables, report.html, field files),
// written atomically; a folder that is not a needlesim results folder is never replaced.
NEEDLESIM_API Results run(const Scenario& scenario, const std::filesystem::path& folder,
                          const RunSettings& settings = {});

// ---------------------------------------------------------------- path planning
// Plans a needle path to the scenario's plan target around its obstacles (docs/planning.md), in
// memory: key results (feasible, planned_miss, entry_offset, entry_angle, bevel_roll, rotations,
// clearance_<name>, planning_time, paths_per_second, error_p50, error_p95, ...) and the tables
// plan, path and error_distribution. A target no path reaches gives feasible 0, the reason in
// warnings and the closest approach in `path`. InputError without a plan section.
NEEDLESIM_API Results plan(const Scenario& scenario);
// The same into a results folder (as `needlesim plan --out`: report.html, the path for ParaView).
NEEDLESIM_API Results plan(const Scenario& scenario, const std::filesystem::path& folder,
                           const RunSettings& settings = {});

// ---------------------------------------------------------------- real-time stepping
// The base motion of one step: the tip's depth along the insertion axis from the entry
// point, and (realtime2d only) the base's lateral offset, the turn of the insertion
// plane and the roll of the bevel about the needle axis from its orientation in the scenario.
struct Command {
  double depth = 0.0;     // m
  double lateral = 0.0;   // m
  double rotation = 0.0;  // rad
  double roll = 0.0;      // rad
  double tilt = 0.0;      // rad, out of the insertion plane (realtime3d; 0 for the 2D engines)
};

// The parts of a Command an engine takes besides the depth (the others must be 0): realtime2d
// lateral, rotation and roll; realtime3d those and tilt; lumped none.
struct Axes {
  bool lateral = false, rotation = false, roll = false, tilt = false;
};

struct State {
  double time = 0.0;             // s, sum of the steps' dt
  double depth = 0.0;            // m, tip along the insertion axis from the entry point
  double axial_force = 0.0;      // N, resistance to insertion (stiffness + cutting + friction)
  double lateral_force = 0.0;    // N, tissue force across the needle (realtime2d; 0 for lumped)
  double stiffness_force = 0.0;  // N, pre-puncture stiffness part
  double cutting_force = 0.0;    // N, cutting part
  double friction_force = 0.0;   // N, shaft friction part
  double tip_x = 0.0, tip_y = 0.0;  // m, tip position (realtime2d: centred tissue frame;
                                    // lumped: (depth, 0) along the insertion axis)
  double tip_deflection = 0.0;   // m, elastic tip deflection (realtime2d; 0 for the rigid lumped needle)
  std::string phase;             // outside, pressing, cutting, inside, through
  // realtime3d (0 otherwise): tip z (centred tissue frame), elastic tip deflection out of the
  // insertion plane, tissue force out of it.
  double tip_z = 0.0, tip_deflection_z = 0.0, out_of_plane_force = 0.0;
};

// The tissue's surface as a viewer draws it: undeformed vertices and triangles.
struct Surface {
  std::vector<double> vertices;  // m, x y z per vertex
  std::vector<int> triangles;    // 3 vertex indices per triangle
  std::string geometry;          // tissue.geometry's file: the surface is an imported tissue's; "" = the block
};

// A tissue.inclusions entry as a viewer draws it, in the tissue frame.
struct Inclusion {
  std::string name;
  std::string shape;                  // sphere, cylinder (its axis along z) or mesh (a group of tissue.geometry)
  double x = 0.0, y = 0.0, z = 0.0;   // m, centre (mesh: the centroid of its elements)
  double radius = 0.0;                // m (mesh: of the sphere of its volume)
  bool target = false;                // the needle aims at it
  std::vector<int> region;            // its material: indices of surface()'s vertices (none for lumped)
};

// What moves on the surface: per vertex, the displacement and a scalar to colour by.
struct SurfaceField {
  std::vector<double> displacement;  // m, x y z per vertex
  std::vector<double> scalar;        // one per vertex
  std::string scalarName = "|u|";    // what the scalar is
  std::string scalarUnit = "m";
};

// The state a surface field is computed from, copied out of a Session by snapshotField: small
// for the reduced and modal back-ends (modal coordinates and filtered path loads), the
// displacement for the direct one, nothing for lumped. Move-only; reuse one to copy into it
// without allocating.
class NEEDLESIM_API FieldSnapshot {
 public:
  FieldSnapshot();
  ~FieldSnapshot();
  FieldSnapshot(FieldSnapshot&&) noexcept;
  FieldSnapshot& operator=(FieldSnapshot&&) noexcept;
  bool empty() const { return !impl_; }  // never filled

 private:
  friend class Session;
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// Steps the `realtime2d` engine (2D FE tissue and a flexible needle), the `realtime3d` engine
// (tetrahedral block, needle bending in two planes) or the `lumped` force model under the
// caller's control, e.g. in a 1 kHz haptic loop. Other engines: InputError. Move-only.
class NEEDLESIM_API Session {
 public:
  explicit Session(const Scenario& scenario);
  ~Session();
  Session(Session&&) noexcept;
  Session& operator=(Session&&) noexcept;

  // Advances by dt [s] > 0 to the commanded base motion. The step guard every caller shares
  // (C++ API, needlesim serve, Python; docs/api.md) refuses with an InputError, stepping
  // nothing: a non-finite argument, an axis the engine does not take (axes()), a pose off the
  // tissue, a tip moving further than half the engine's spacing in one step.
  const State& step(const Command& command, double dt);
  const State& step(double depth, double dt) { return step(Command{depth, 0.0, 0.0, 0.0}, dt); }
  const State& state() const;
  // Back to the state before the first step.
  void reset();
  std::string engine() const;
  Axes axes() const;

  // realtime2d and realtime3d only (InputError for lumped), centred tissue frame, dimension()
  // coordinates (x, y[, z]) per point:
  std::vector<double> nodePositions() const;      // m, undeformed mesh nodes
  std::vector<double> nodeDisplacements() const;  // m, per node
  std::vector<double> needleShape(int points = 41) const;  // m, base to tip, points >= 2
  int dimension() const;  // 2 (realtime2d, lumped) or 3 (realtime3d)

  // For a viewer, every engine (docs/serve.md), in the tissue frame x y z (x depth):
  // the tissue's surface (realtime3d: the tetrahedral block's boundary triangles, outward, over
  // its nodes; realtime2d: its mesh as triangles in z = 0; lumped: the block's mid-plane, which
  // does not deform), and the needle's centre line, base to tip.
  Surface surface() const;
  // The scenario's tissue.inclusions, with the vertices of surface() their material holds
  // (realtime2d, realtime3d; their mean displacement is the inclusion's, as in inclusions.csv).
  std::vector<Inclusion> inclusions() const;
  // Fills `field` for the current step (reuses its storage; sized for surface()).
  void surfaceField(SurfaceField& field) const;
  // The same field in two parts, so that a control loop does not compute it: snapshotField
  // copies the state of the current step (cheap; no allocation once `snapshot` holds one of this
  // session), and surfaceField(snapshot, field) computes the field from it. The second reads
  // only what step() leaves unchanged (mesh, mode shapes, path flexibility), so another thread
  // may run it while step() runs, though not during reset(), a move or the destructor.
  // InputError for an empty snapshot or one of a session with another mesh.
  void snapshotField(FieldSnapshot& snapshot) const;
  void surfaceField(const FieldSnapshot& snapshot, SurfaceField& field) const;
  std::vector<double> needleCentreLine(int points = 41) const;  // m, x y z per point, points >= 2

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// ---------------------------------------------------------------- fits and studies
struct FitOptions {
  std::vector<std::filesystem::path> data;  // CSV files with units in the header
  std::string law = "auto";  // a law or analysis of `needlesim fit --law` (docs/fitting.md)
  double needleDiameter = 0.0;  // m, insertion analyses
  double thickness = 0.0;       // m, insertion analyses (phantom length)
  std::filesystem::path out;    // output folder; "" = the program's default
  bool write = false;           // write fit.json and report.html
  bool overwrite = false;
};

struct FitParameter {
  std::string name;
  double value = 0.0;
  std::string unit;
  double stdError = 0.0;  // NaN where the fit cannot estimate it (fit.json: null)
};

struct FitResults {
  std::string law;                       // the law chosen (for "auto": the best)
  std::vector<FitParameter> parameters;  // SI
  std::string table;                     // what `needlesim fit` prints
  std::string materialYaml;              // a scenario-ready block ("" where none)
  std::filesystem::path folder;          // where it was written ("" when not written)
};

NEEDLESIM_API FitResults fit(const FitOptions& options);

struct SweepOptions {
  std::filesystem::path out;  // study folder; "" = the study's directory (results/<name>)
  bool resume = false;        // reuse the cases already complete
  bool progress = false;
  int parallel = -1;          // cases at once; -1 = the study's setting
};

struct SweepSummary {
  std::filesystem::path folder;  // holds study.csv, study.json, report.html and a folder per case
  int cases = 0, ran = 0, reused = 0;
  std::vector<int> failed;       // 1-based indices of the cases that failed
};

// Runs a study file (docs/studies.md).
NEEDLESIM_API SweepSummary sweep(const std::filesystem::path& studyFile, const SweepOptions& options = {});

}  // namespace needlesim::api
