#pragma once
// Shared pieces of the compiled extension needlesim._core (pybind11): the
// scenario object and the checks of arguments given from Python.
#include <pybind11/pybind11.h>

#include <filesystem>
#include <string>

#include "needlesim/scenario/scenario.hpp"

namespace needlesim::python {

struct PyScenario {
  Scenario scenario;
  std::string text;               // the YAML it came from (for with_values)
  std::filesystem::path folder;  // the scenario file's folder (relative data paths); empty for YAML text
};

// needlesim.ArgumentTypeError (InputError and TypeError): an argument of the wrong type,
// "<call>: <what> must be <allowed>, not <type>".
[[noreturn]] void throwArgumentType(const std::string& call, const std::string& what, const std::string& allowed,
                                    const pybind11::handle& got);

// InputError "<python>: call(arg): must be a finite number (got 'nan'); allowed: ..." unless v is finite.
void requireFinite(const std::string& call, const std::string& arg, double v, const std::string& allowed);
// requireFinite and v > 0.
void requirePositive(const std::string& call, const std::string& arg, double v, const std::string& allowed);

// The insertion profile at time t (a MotionSample: depth, velocity, rotation, roll).
pybind11::object motionAt(const PyScenario& s, double t);

// needlesim._core.Session and its step result (session_bindings.cpp).
void bindSessions(pybind11::module_& m);

}  // namespace needlesim::python
