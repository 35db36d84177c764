#pragma once
// A ResultSink that keeps everything in memory: for the Python bindings,
// embedding applications and tests that run an engine without files.
#include <map>
#include <string>
#include <vector>

#include "needlesim/engines/engine.hpp"

namespace needlesim {

class MemorySink : public ResultSink {
 public:
  struct Value {
    double value;
    std::string unit, meaning;
  };
  void table(const std::string& name, io::Table t) override { tables[name] = std::move(t); }
  void result(const std::string& key, double value, const std::string& unit, const std::string& meaning) override {
    results[key] = Value{value, unit, meaning};
    order.push_back(key);
  }
  void plot(io::Plot p) override { plots.push_back(std::move(p)); }
  void note(const std::string& text) override { notes.push_back(text); }
  void warning(const std::string& text) override { warnings.push_back(text); }

  std::map<std::string, io::Table> tables;
  std::map<std::string, Value> results;
  std::vector<std::string> order;
  std::vector<io::Plot> plots;
  std::vector<std::string> notes;
  std::vector<std::string> warnings;
};

// Runs the scenario's engine into memory (no files). Throws InputError for an
// engine this build lacks, SolverError when the engine stops.
MemorySink runInMemory(const Scenario& scenario, const RunOptions& options = {false});

}  // namespace needlesim
