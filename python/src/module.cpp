// needlesim._core, the compiled part of the Python package (python/needlesim):
// scenarios, any engine run in memory or to a results folder, parameter
// variation, the lumped force model for kHz loops; sessions in session_bindings.cpp.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <fmt/format.h>

#include <cctype>
#include <cmath>
#include <new>
#include <optional>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "needlesim/core/embedded.hpp"
#include "needlesim/core/error.hpp"
#include "needlesim/core/progress.hpp"
#include "needlesim/core/version.hpp"
#include "needlesim/engines/memory_sink.hpp"
#include "needlesim/planning/plan_run.hpp"
#include "needlesim/engines/run_scenario.hpp"
#include "needlesim/forces/lumped_model.hpp"
#include "needlesim/scenario/reader.hpp"
#include "needlesim/scenario/schema.hpp"
#include "needlesim/scenario/yaml_document.hpp"
#include "needlesim/study/field_path.hpp"
#include "needlesim/study/study.hpp"
#include "needlesim/study/with_values.hpp"
#include "bindings.hpp"

namespace py = pybind11;
using namespace pybind11::literals;

namespace needlesim::python {

namespace {
PyObject* argumentTypeError = nullptr;  // needlesim.ArgumentTypeError, made in PYBIND11_MODULE
}  // namespace

void throwArgumentType(const std::string& call, const std::string& what, const std::string& allowed,
                       const py::handle& got) {
  const std::string type = py::str(py::type::of(got).attr("__name__")).cast<std::string>();
  PyErr_SetString(argumentTypeError, (call + ": " + what + " must be " + allowed + ", not " + type).c_str());
  throw py::error_already_set();
}

void requireFinite(const std::string& call, const std::string& arg, double v, const std::string& allowed) {
  if (!std::isfinite(v))
    throw InputError(SourceLocation{"<python>", 0, 0}, call + "(" + arg + ")", fmt::format("{}", v), "must be a finite number",
                     allowed);
}

void requirePositive(const std::string& call, const std::string& arg, double v, const std::string& allowed) {
  requireFinite(call, arg, v, allowed);
  if (!(v > 0.0))
    throw InputError(SourceLocation{"<python>", 0, 0}, call + "(" + arg + ")", fmt::format("{}", v), "must be > 0", allowed);
}

namespace {

constexpr const char* kLoadDoc = R"(Read and validate a scenario.

`path_or_yaml` is read as a file when it is a pathlib.Path (any os.PathLike),
when it names an existing file, or when it is one line that ends in .yaml,
.yml or .json or holds no ':' (such a path that does not exist raises
needlesim.InputError "file not found"). Otherwise (text with a newline, or one
line with ':' such as "{tissue: ...}") it is YAML text. Errors raise
needlesim.InputError naming file, line, field, value and what is allowed.)";

bool endsWith(const std::string& s, const std::string& tail) {
  if (s.size() < tail.size()) return false;
  for (std::size_t i = 0; i < tail.size(); ++i)
    if (std::tolower(static_cast<unsigned char>(s[s.size() - tail.size() + i])) != tail[i]) return false;
  return true;
}

// The rule of kLoadDoc for a str argument.
bool looksLikePath(const std::string& s) {
  if (s.find('\n') != std::string::npos) return false;
  std::error_code ec;  // a name the file system refuses (too long) is not a file
  if (std::filesystem::is_regular_file(s, ec)) return true;
  return endsWith(s, ".yaml") || endsWith(s, ".yml") || endsWith(s, ".json") || s.find(':') == std::string::npos;
}

PyScenario loadFile(const std::filesystem::path& path) {
  const std::string name = path.string();
  const auto refused = [&](const std::string& problem, const std::string& allowed) {
    return InputError(SourceLocation{name, 0, 0}, "", "", problem, allowed);
  };
  std::error_code ec;
  const std::filesystem::file_status status = std::filesystem::status(path, ec);
  if (std::filesystem::is_directory(status)) throw refused("is a folder", "a scenario file (YAML) or YAML text");
  if (!std::filesystem::exists(status)) throw refused("file not found", "an existing scenario file or YAML text");
  // a device, pipe or socket could be read without end (/dev/zero)
  if (!std::filesystem::is_regular_file(status))
    throw refused("is not a regular file (a device, pipe or socket)", "a scenario file (YAML) or YAML text");
  std::string text = scenario::readYamlFile(path, "a scenario file (see docs/scenario-format.md)");  // size-checked
  return PyScenario{scenario::readText(text, name), text, {}};
}

bool isPathLike(const py::handle& o) { return py::hasattr(o, "__fspath__"); }

// A str or pathlib.Path (any os.PathLike) as the file system's bytes (os.fsencode: a name
// that is not UTF-8 keeps its bytes).
std::string pathText(const py::handle& o) {
  return py::module_::import("os").attr("fsencode")(o).cast<py::bytes>().cast<std::string>();
}

// A str as UTF-8, or nothing when it holds lone surrogates (undecodable bytes of a file name).
std::optional<std::string> utf8Of(const py::handle& s) {
  Py_ssize_t size = 0;
  const char* data = PyUnicode_AsUTF8AndSize(s.ptr(), &size);
  if (data == nullptr) {
    PyErr_Clear();
    return std::nullopt;
  }
  return std::string(data, static_cast<std::size_t>(size));
}

PyScenario loadFile(const std::string& name) {
  PyScenario s = loadFile(std::filesystem::path(name));
  s.folder = study::dataFolderOf(name);
  return s;
}

PyScenario load(const py::object& pathOrYaml) {
  if (py::isinstance<py::str>(pathOrYaml)) {
    const std::optional<std::string> s = utf8Of(pathOrYaml);
    if (!s) return loadFile(pathText(pathOrYaml));  // not text: a file name with undecodable bytes
    if (looksLikePath(*s)) return loadFile(*s);
    return PyScenario{scenario::readText(*s, "<python>"), *s, {}};
  }
  if (isPathLike(pathOrYaml)) return loadFile(pathText(pathOrYaml));
  throwArgumentType("needlesim.load", "path_or_yaml", "a str (path or YAML text) or a pathlib.Path", pathOrYaml);
}

// with_values: the base YAML with fields set; a bad field path is an InputError
// naming the path and the bad part's position.
// A with_values value as YAML text: a str as written ("3 N/m"), a bool, or a finite number.
std::string valueText(const std::string& path, const py::handle& v) {
  if (py::isinstance<py::str>(v)) {
    if (std::optional<std::string> text = utf8Of(v)) return *text;
    throw InputError(SourceLocation{"<python with_values>", 0, 0}, path, "", "is not valid text (lone surrogates)",
                     "a str of Unicode characters such as '3 N/m'");
  }
  if (py::isinstance<py::bool_>(v)) return v.cast<bool>() ? "true" : "false";
  if (py::isinstance<py::int_>(v) || py::isinstance<py::float_>(v)) {
    double x = v.cast<double>();
    requireFinite("with_values", path, x, "a finite number, or a str with its unit such as '3 N/m'");
    return py::repr(v).cast<std::string>();
  }
  throwArgumentType("Scenario.with_values", "the value of '" + path + "'", "a str (e.g. '3 N/m'), a number or a bool", v);
}

// Relative data paths, in the scenario file or among the values, resolve from the scenario
// file's folder (study::withValuesYaml).
PyScenario withValues(const PyScenario& s, const py::object& values) {
  if (!py::isinstance<py::dict>(values))
    throwArgumentType("Scenario.with_values", "values", "a dict {field path: value}", values);
  std::vector<std::pair<std::string, std::string>> assignments;
  for (const auto& [key, object] : values.cast<py::dict>()) {
    if (!py::isinstance<py::str>(key))
      throwArgumentType("Scenario.with_values", "each key", "a str field path such as 'tissue.friction.C_p'", key);
    const std::optional<std::string> path = utf8Of(key);
    if (!path)
      throw InputError(SourceLocation{"<python with_values>", 0, 0}, "with_values key", "", "is not valid text (lone surrogates)",
                       "a field path such as 'tissue.friction.C_p'");
    assignments.emplace_back(*path, valueText(*path, object));
  }
  const SourceLocation where{"<python with_values>", 0, 0};
  std::string text = study::withValuesYaml(s.text, assignments, where, "with_values key", s.folder);
  return PyScenario{scenario::readText(text, where.file), text, s.folder};
}

// A table as (columns [(name, unit)], rows x columns float64 array).
py::tuple tableTuple(const io::Table& t) {
  py::list columns;
  for (const auto& c : t.columns()) columns.append(py::make_tuple(c.name, c.unit));
  py::array_t<double> data({t.rows(), t.columns().size()});
  auto a = data.mutable_unchecked<2>();
  for (std::size_t r = 0; r < t.rows(); ++r)
    for (std::size_t c = 0; c < t.columns().size(); ++c) a(r, c) = t.at(r, c);
  return py::make_tuple(columns, data);
}

// What needlesim.Results is made of (python/needlesim/results.py).
py::dict toDict(const MemorySink& s) {
  py::dict results, tables;
  for (const auto& k : s.order) {
    const auto& v = s.results.at(k);
    results[py::str(k)] = py::make_tuple(v.value, v.unit, v.meaning);
  }
  for (const auto& [name, t] : s.tables) tables[py::str(name)] = tableTuple(t);
  py::dict out;
  out["results"] = results;
  out["tables"] = tables;
  out["notes"] = s.notes;
  out["warnings"] = s.warnings;  // what the CLI prints as "warning: ..."
  return out;
}

py::dict runInMemoryDict(const PyScenario& s) {
  MemorySink sink;
  {
    py::gil_scoped_release release;
    sink = runInMemory(s.scenario);
  }
  return toDict(sink);
}

// Plans the scenario's plan section in memory (docs/planning.md): a dict as run_in_memory's.
py::dict planInMemoryDict(const PyScenario& s) {
  MemorySink sink;
  {
    py::gil_scoped_release release;
    const planning::PlanOutcome o = planning::planScenario(s.scenario);
    planning::reportPlan(s.scenario, o, sink);
  }
  return toDict(sink);
}

// Runs into the results folder `out`: {'folder': its path, 'tables': as run_in_memory's, exact}
// (Python reads the rest back from the folder).
// A results folder that cannot be made or written (a file system error, a write that
// failed) is an InputError about `out`, with the file system's or the writer's message.
RunOutcome runScenarioTo(const Scenario& sc, const std::string& out, bool overwrite, const RunOptions& ro) {
  try {
    return runScenario(sc, out, overwrite, ro);
  } catch (const InputError&) {
    throw;
  } catch (const SolverError&) {
    throw;
  } catch (const RunInterrupted&) {
    throw;
  } catch (const std::bad_alloc&) {
    throw;
  } catch (const std::exception& e) {
    throw InputError(SourceLocation{"<python>", 0, 0}, "needlesim.run(out)", out,
                     std::string("cannot be written as a results folder: ") + e.what(),
                     "a folder path where needlesim can create and write files");
  }
}

py::dict runToFolder(const PyScenario& s, const py::object& outArg, bool overwrite) {
  if (!py::isinstance<py::str>(outArg) && !isPathLike(outArg))
    throwArgumentType("needlesim.run", "out", "a str or a pathlib.Path", outArg);
  const std::string out = pathText(outArg);
  if (out.find('\0') != std::string::npos)
    throw InputError(SourceLocation{"<python>", 0, 0}, "needlesim.run(out)", out, "holds a NUL character",
                     "a folder path without NUL characters");
  RunOptions ro;
  ro.progress = false;
  ro.printWarnings = false;  // they are in Results.warnings
  RunOutcome o;
  {
    py::gil_scoped_release release;
    o = runScenarioTo(s.scenario, out, overwrite, ro);
  }
  py::dict tables;
  for (const auto& [name, t] : o.tables) tables[py::str(name)] = tableTuple(t);
  py::dict d;
  d["folder"] = py::bytes(o.folder.string());  // the file system's bytes (os.fsdecode in Python)
  d["tables"] = tables;
  return d;
}

}  // namespace
}  // namespace needlesim::python

using namespace needlesim;
using namespace needlesim::python;

namespace {

// InputError and SolverError with their subclasses, and the translation of every C++ error.
void registerErrors(py::module_& m) {
  static py::exception<InputError> inputError(m, "InputError", PyExc_ValueError);
  static py::exception<SolverError> solverError(m, "SolverError", PyExc_RuntimeError);
  // Subclasses that also derive from the builtin exception of the same meaning.
  // The message as given (KeyError would quote it).
  const py::dict plainText("__str__"_a = py::handle(PyExc_BaseException).attr("__str__"));
  const auto subclass = [&](const char* name, PyObject* builtin, const char* doc) {
    PyObject* cls = PyErr_NewExceptionWithDoc((std::string("needlesim._core.") + name).c_str(), doc,
                                              py::make_tuple(inputError, py::handle(builtin)).ptr(), plainText.ptr());
    if (cls == nullptr) throw py::error_already_set();
    m.add_object(name, py::handle(cls));
    return cls;
  };
  argumentTypeError = subclass("ArgumentTypeError", PyExc_TypeError,
                               "An argument of the wrong type (an InputError and a TypeError).");
  subclass("NotFoundError", PyExc_FileNotFoundError,
           "A file or folder that does not exist (an InputError and a FileNotFoundError).");
  subclass("UnknownNameError", PyExc_KeyError,
           "A table column, field array or result key that does not exist (an InputError and a KeyError).");
  // Every C++ error reaches Python as InputError or SolverError (docs/python.md "Errors"):
  // needlesim's own errors as the CLI reports them (a bad input, a solver that stops), a file
  // system error as the input that named the file, anything else as a SolverError (a RuntimeError).
  // The message as text even where it holds bytes that are not UTF-8 (escaped, as \xff).
  static const auto setError = [](PyObject* type, const std::string& what) {
    py::object text = py::reinterpret_steal<py::object>(
        PyUnicode_DecodeUTF8(what.data(), static_cast<Py_ssize_t>(what.size()), "backslashreplace"));
    if (!text) return;  // the decoding error is then the one raised
    PyErr_SetObject(type, text.ptr());
  };
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const py::builtin_exception&) {
      throw;  // pybind11's own (TypeError, ValueError, ...) go to its translator
    } catch (const InputError& e) {
      setError(inputError.ptr(), e.what());
    } catch (const SolverError& e) {
      setError(solverError.ptr(), e.what());
    } catch (const RunInterrupted& e) {
      setError(PyExc_KeyboardInterrupt, e.what());
    } catch (const Error& e) {
      setError(inputError.ptr(), e.what());
    } catch (const std::filesystem::filesystem_error& e) {
      setError(inputError.ptr(), printable(e.what(), 4000));
    } catch (const std::bad_alloc&) {
      setError(solverError.ptr(), "not enough memory for this run: use a coarser mesh or fewer steps");
    } catch (const std::exception& e) {
      setError(solverError.ptr(), printable(e.what(), 4000));
    }
  });
}

void bindScenario(py::module_& m) {
  py::class_<PyScenario>(m, "Scenario", "A validated scenario (SI inside)")
      .def_property_readonly("name", [](const PyScenario& s) { return s.scenario.name; })
      .def_property_readonly("engine", [](const PyScenario& s) { return s.scenario.model.engine; })
      .def_property_readonly("duration", [](const PyScenario& s) { return s.scenario.totalDuration(); })
      .def_property_readonly("yaml", [](const PyScenario& s) { return s.text; })
      .def("__repr__",
           [](const PyScenario& s) {
             return fmt::format("<Scenario '{}' ({}), {:g} s, from {}>", s.scenario.name, s.scenario.model.engine,
                                s.scenario.totalDuration(), s.scenario.source);
           })
      .def("motion_at", &motionAt, py::arg("t"),
           "The insertion profile at time t [s]: a MotionSample with depth [m], velocity [m/s], rotation [rad] (in "
           "the plane) and roll [rad] (about the axis, from the bevel orientation), the arguments of Session.step.")
      .def("with_values", &withValues, py::arg("values"),
           "A copy with fields set, e.g. {'tissue.friction.C_p': '3 N/m', 'insertion.profile[0].insert.speed': "
           "'5 mm/s', 'model.lumped.relaxation_time': '0.1 s'}; validated like a file. Keys are field paths as in a study "
           "(docs/studies.md); values are str (with units), finite numbers or bools. A bad path or "
           "value raises needlesim.InputError.");
}

void bindFunctions(py::module_& m) {
  m.def("load", &load, py::arg("path_or_yaml"), kLoadDoc);
  m.def("default_scenario", [] { return PyScenario{scenario::defaultScenario(), std::string(embedded::kDefaultScenario)}; });
  m.def("run_in_memory", &runInMemoryDict, py::arg("scenario"),
        "Runs the scenario's engine in memory: {'results': {key: (value, unit, meaning)}, 'tables': {name: "
        "([(column, unit)], rows x columns array)}, 'notes': [...], 'warnings': [...]}.");
  m.def("plan_in_memory", &planInMemoryDict, py::arg("scenario"),
        "Plans a path to the scenario's plan target (docs/planning.md): results and tables as run_in_memory's "
        "(plan, path, error_distribution)");
  m.def("run_to_folder", &runToFolder, py::arg("scenario"), py::arg("out"), py::arg("overwrite") = false,
        "Runs the scenario's engine into the results folder `out` (a str or pathlib.Path): {'folder': its path, "
        "'tables': {name: ([(column, unit)], rows x columns array)}}.");
  m.def("schema", [] { return scenario::schemaText(); });
  m.def(
      "engines",
      [] {
        std::vector<std::string> names;
        for (const auto& e : engineRegistry()) names.push_back(e.name);
        return names;
      },
      "The names of the engines in this build (model.engine).");
}

void bindLumpedForceModel(py::module_& m) {
  py::class_<forces::LumpedForceModel>(m, "LumpedForceModel",
                                       "Seed 003 lumped insertion force, stepped by the caller (haptic loops)")
      .def(py::init([](const PyScenario& s) {
             return forces::LumpedForceModel(s.scenario.tissue, s.scenario.needle, s.scenario.insertion.entry_angle,
                                             s.scenario.model.lumped.relaxation_time);
           }),
           py::arg("scenario"))
      .def(
          "step",
          [](forces::LumpedForceModel& m, double depth, double velocity, double dt) {
            requireFinite("LumpedForceModel.step", "depth", depth, "a tip depth in m");
            requireFinite("LumpedForceModel.step", "velocity", velocity, "a tip velocity in m/s");
            requirePositive("LumpedForceModel.step", "dt", dt, "a time step > 0 s");
            auto f = m.step(depth, velocity, dt);
            return py::make_tuple(f.total(), f.stiffness, f.cutting, f.friction);
          },
          py::arg("depth"), py::arg("velocity"), py::arg("dt"),
          "Advance to tip depth [m] at velocity [m/s] over dt [s]; returns (total, stiffness, cutting, friction) [N].")
      .def("reset", &forces::LumpedForceModel::reset);
}

}  // namespace

PYBIND11_MODULE(_core, m) {
  m.doc() = "needlesim's compiled core; use the package needlesim (python/needlesim/__init__.py)";
  m.attr("__version__") = kVersion;
  m.attr("git_revision") = kGitRevision;
  registerErrors(m);
  bindScenario(m);
  bindFunctions(m);
  bindLumpedForceModel(m);
  bindSessions(m);
}
