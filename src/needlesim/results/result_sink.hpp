#pragma once
// Where a run reports: the interface every engine writes its results through
// (a results folder, results/results_folder.hpp; memory, engines/memory_sink.hpp).
#include <string>

#include "needlesim/io/html_report.hpp"
#include "needlesim/io/table.hpp"

namespace needlesim {
namespace io {
class FieldSeries;
}

class ResultSink {
 public:
  virtual ~ResultSink() = default;
  // A time series or other table; written as <name>.csv.
  virtual void table(const std::string& name, io::Table table) = 0;
  // A key result for summary.json and the report's table.
  virtual void result(const std::string& key, double value, const std::string& unit,
                      const std::string& meaning) = 0;
  virtual void plot(io::Plot plot) = 0;
  virtual void note(const std::string& text) = 0;
  // Something the user must see: the results may not mean what they seem
  // (not quasi-static, energy balance off, values clipped, stopped early).
  // A results folder prints it at once and lists it in summary.json
  // ("warnings") and at the top of the report; other sinks keep it as a note.
  virtual void warning(const std::string& text) { note("warning: " + text); }
  // A field time series for ParaView (<name>.h5 + <name>.xdmf), streamed step
  // by step; nullptr when this sink keeps no fields (tests, sweeps without fields).
  virtual io::FieldSeries* fields(const std::string& /*name*/, int /*dim*/) { return nullptr; }
};

}  // namespace needlesim
