// Python bindings: scenarios, any engine run in memory or to a results folder,
// parameter variation, and the lumped force model for kHz loops.
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <fstream>
#include <iterator>

#include "needlesim/core/embedded.hpp"
#include "needlesim/core/error.hpp"
#include "needlesim/core/version.hpp"
#include "needlesim/engines/memory_sink.hpp"
#include "needlesim/engines/run_scenario.hpp"
#include "needlesim/forces/lumped_model.hpp"
#include "needlesim/scenario/reader.hpp"
#include "needlesim/scenario/schema.hpp"
#include "needlesim/study/study.hpp"

namespace py = pybind11;
using namespace needlesim;

namespace {

struct PyScenario {
  Scenario scenario;
  std::string text;  // the YAML it came from (for with_values)
};

PyScenario load(const std::string& pathOrYaml) {
  bool isText = pathOrYaml.find('\n') != std::string::npos || pathOrYaml.find(':') != std::string::npos;
  std::string text = pathOrYaml;
  if (!isText) {
    std::ifstream in(pathOrYaml);
    if (!in) throw InputError(SourceLocation{pathOrYaml, 0, 0}, "", "", "cannot be opened", "a scenario file or YAML text");
    text.assign(std::istreambuf_iterator<char>(in), {});
  }
  return PyScenario{scenario::readText(text, isText ? "<python>" : pathOrYaml), text};
}

py::dict toDict(const MemorySink& s) {
  py::dict results, tables;
  for (const auto& [k, v] : s.results) results[py::str(k)] = py::make_tuple(v.value, v.unit);
  for (const auto& [name, t] : s.tables) {
    py::dict cols;
    for (const auto& c : t.columns()) cols[py::str(c.name)] = t.column(c.name);
    tables[py::str(name)] = cols;
  }
  py::dict out;
  out["results"] = results;
  out["tables"] = tables;
  return out;
}

}  // namespace

PYBIND11_MODULE(needlesim, m) {
  m.doc() = "needlesim: needle insertion into soft tissue (forces, deflection, steering, deformation)";
  m.attr("__version__") = kVersion;
  m.attr("git_revision") = kGitRevision;

  static py::exception<InputError> inputError(m, "InputError", PyExc_ValueError);
  static py::exception<SolverError> solverError(m, "SolverError", PyExc_RuntimeError);
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const InputError& e) {
      PyErr_SetString(inputError.ptr(), e.what());
    } catch (const SolverError& e) {
      PyErr_SetString(solverError.ptr(), e.what());
    }
  });

  py::class_<PyScenario>(m, "Scenario", "A validated scenario (SI inside)")
      .def_property_readonly("name", [](const PyScenario& s) { return s.scenario.name; })
      .def_property_readonly("engine", [](const PyScenario& s) { return s.scenario.model.engine; })
      .def_property_readonly("duration", [](const PyScenario& s) { return s.scenario.totalDuration(); })
      .def_property_readonly("yaml", [](const PyScenario& s) { return s.text; })
      .def(
          "with_values",
          [](const PyScenario& s, const std::map<std::string, std::string>& values) {
            study::Case c;
            for (const auto& [k, v] : values) c.assignments.emplace_back(k, v);
            std::string text = study::caseYaml(s.text, c);
            return PyScenario{scenario::readText(text, "<python with_values>"), text};
          },
          py::arg("values"),
          "A copy with fields set, e.g. {'tissue.friction.C_p': '3 N/m'}; validated like a file.");

  m.def("load", &load, py::arg("path_or_yaml"), "Read and validate a scenario file (or YAML text).");
  m.def("default_scenario", [] { return PyScenario{scenario::defaultScenario(), std::string(embedded::kDefaultScenario)}; });
  m.def(
      "run",
      [](const PyScenario& s, const std::string& out, bool overwrite) -> py::object {
        if (out.empty()) {
          py::gil_scoped_release release;
          MemorySink sink = runInMemory(s.scenario);
          py::gil_scoped_acquire acquire;
          return toDict(sink);
        }
        RunOptions ro;
        ro.progress = false;
        RunOutcome o = runScenario(s.scenario, out, overwrite, ro);
        py::dict results;
        for (const auto& r : o.results) results[py::str(r.key)] = py::make_tuple(r.value, r.unit);
        py::dict d;
        d["results"] = results;
        d["folder"] = o.folder.string();
        return d;
      },
      py::arg("scenario"), py::arg("out") = "", py::arg("overwrite") = false,
      "Run the scenario's engine. Without `out`: in memory, returns {'results': {key: (value, unit)}, 'tables': "
      "{name: {column: [values]}}}. With `out`: writes the results folder.");
  m.def("schema", [] { return scenario::schemaText(); });

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
            auto f = m.step(depth, velocity, dt);
            return py::make_tuple(f.total(), f.stiffness, f.cutting, f.friction);
          },
          py::arg("depth"), py::arg("velocity"), py::arg("dt"),
          "Advance to tip depth [m] at velocity [m/s] over dt [s]; returns (total, stiffness, cutting, friction) [N].")
      .def("reset", &forces::LumpedForceModel::reset);
}
