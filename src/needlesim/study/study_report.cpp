#include "needlesim/study/study_report.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <set>

#include "needlesim/results/display_units.hpp"

namespace needlesim::study {

namespace {

constexpr std::size_t kCaseColumn = 0, kCompleteColumn = 1, kFirstInputColumn = 2;
// An input with at most this many distinct values has them all listed.
constexpr std::size_t kListedValues = 8;

// A value given in SI with its unit as the study shows it ("0.2399 N", "2.5 mm", "1", "n/a"),
// in the unit of values up to `largest` (a range's ends share one unit).
std::string valueText(const StudyResults& r, double v, const std::string& unit, double largest) {
  return results::shownText(v, unit, r.display, "{:.6g}", largest);
}

// A column's value as the report's table shows it, without the unit (in its header, chosen
// for the column's largest value).
std::string cellText(const StudyResults& r, double v, const std::string& unit, double largest) {
  if (std::isnan(v)) return "n/a";
  if (std::isinf(v)) return "none";
  return fmt::format("{:.6g}", units::shown(v, unit, r.display, largest).value);
}

// The largest finite magnitude in column `col` (0 if none).
double columnLargest(const StudyResults& r, std::size_t col) {
  double m = 0.0;
  for (std::size_t row = 0; row < r.table.rows(); ++row)
    if (const double v = r.table.at(row, col); std::isfinite(v)) m = std::max(m, std::abs(v));
  return m;
}

// A column's header as the report and plots name it: "exit_force [N]".
std::string labelWithUnit(const std::string& name, const std::string& unit) { return name + " [" + unit + "]"; }

bool isComplete(const StudyResults& r, std::size_t row) { return r.table.at(row, kCompleteColumn) == 1.0; }

// The values of column `col` in the complete cases.
std::vector<double> completeValues(const StudyResults& r, std::size_t col) {
  std::vector<double> v;
  for (std::size_t row = 0; row < r.table.rows(); ++row)
    if (isComplete(r, row)) v.push_back(r.table.at(row, col));
  return v;
}

std::size_t completeCount(const StudyResults& r) {
  std::size_t n = 0;
  for (std::size_t row = 0; row < r.table.rows(); ++row) n += isComplete(r, row) ? 1 : 0;
  return n;
}

// The varied field of input k and its (SI) unit in the table.
const std::string& inputField(const StudyResults& r, std::size_t k) { return r.spec.parameters[k].field; }
const std::string& inputUnit(const StudyResults& r, std::size_t k) {
  return r.table.columns()[kFirstInputColumn + k].unit;
}
// A column's header as the report names it, in the unit its values (up to `largest`) are shown in.
std::string shownLabel(const StudyResults& r, const std::string& name, const std::string& si_unit, double largest) {
  return labelWithUnit(name, r.display.unitFor(si_unit, largest));
}

// The case table of the report: case, the inputs, the varying outputs.
io::HtmlTable caseTable(const StudyResults& r, const OutputColumns& outputs) {
  const auto& cols = r.table.columns();
  const std::size_t inputs = r.spec.parameters.size();
  io::HtmlTable t;
  t.caption = "Cases";
  t.groups = {{"", 1}, {"inputs (varied)", inputs}};
  if (!outputs.varying.empty()) t.groups.emplace_back("outputs", outputs.varying.size());
  t.header.push_back("case");
  for (std::size_t k = 0; k < inputs; ++k)
    t.header.push_back(shownLabel(r, inputField(r, k), inputUnit(r, k), columnLargest(r, kFirstInputColumn + k)));
  for (std::size_t c : outputs.varying) t.header.push_back(shownLabel(r, cols[c].name, cols[c].unit, columnLargest(r, c)));
  for (std::size_t row = 0; row < std::min(r.table.rows(), kMaxReportRows); ++row) {
    std::vector<std::string> cells{fmt::format("{}", r.table.at(row, kCaseColumn))};
    for (std::size_t k = 0; k < inputs; ++k) {
      const double v = r.table.at(row, kFirstInputColumn + k), largest = columnLargest(r, kFirstInputColumn + k);
      cells.push_back(std::isfinite(v) ? cellText(r, v, inputUnit(r, k), largest) : r.cases[row].assignments[k].second);
    }
    for (std::size_t c : outputs.varying)
      cells.push_back(isComplete(r, row) ? cellText(r, r.table.at(row, c), cols[c].unit, columnLargest(r, c))
                                         : "not complete");
    t.rows.push_back(std::move(cells));
  }
  return t;
}

// Each varying output against each input (for the inputs that are numbers).
std::vector<io::Plot> outputPlots(const StudyResults& r, const OutputColumns& outputs) {
  const auto& cols = r.table.columns();
  std::vector<io::Plot> plots;
  for (std::size_t k = 0; k < r.spec.parameters.size(); ++k) {
    const std::vector<double> x = completeValues(r, kFirstInputColumn + k);
    if (std::none_of(x.begin(), x.end(), [](double v) { return std::isfinite(v); })) continue;
    for (std::size_t c : outputs.varying) {
      io::Plot p{cols[c].name + " against " + inputField(r, k), labelWithUnit(inputField(r, k), inputUnit(r, k)),
                 labelWithUnit(cols[c].name, cols[c].unit), {}};
      p.series.push_back({cols[c].name, x, completeValues(r, c), true, false});
      plots.push_back(results::inDisplayUnits(std::move(p), r.display));
    }
  }
  return plots;
}

}  // namespace

std::string inputColumnName(const std::string& field) { return "input: " + field; }

std::size_t firstOutputColumn(const StudyResults& r) { return kFirstInputColumn + r.spec.parameters.size(); }

bool constantOverCases(const std::vector<double>& values) {
  if (values.size() < 2 || !std::isfinite(values.front())) return false;
  const double ref = values.front();
  return std::all_of(values.begin(), values.end(), [ref](double v) {
    return std::isfinite(v) && std::abs(v - ref) <= kConstantTolerance * std::max(std::abs(v), std::abs(ref));
  });
}

OutputColumns splitOutputs(const StudyResults& r) {
  OutputColumns out;
  for (std::size_t c = firstOutputColumn(r); c < r.table.columns().size(); ++c)
    (constantOverCases(completeValues(r, c)) ? out.constant : out.varying).push_back(c);
  return out;
}

std::string constantLine(const StudyResults& r, const OutputColumns& outputs) {
  if (outputs.constant.empty()) return {};
  std::string line = "constant over all cases: ";
  for (std::size_t i = 0; i < outputs.constant.size(); ++i) {
    const io::Column& col = r.table.columns()[outputs.constant[i]];
    const double v = completeValues(r, outputs.constant[i]).front();
    line += (i ? ", " : "") + col.name + " = " + valueText(r, v, col.unit, -1.0);
  }
  return line;
}

std::vector<std::string> inputLines(const StudyResults& r) {
  std::vector<std::string> lines;
  for (std::size_t k = 0; k < r.spec.parameters.size(); ++k) {
    std::vector<std::string> distinct;  // as written, in the order of the cases
    std::set<std::string> seen;
    for (const auto& c : r.cases)
      if (seen.insert(c.assignments[k].second).second) distinct.push_back(c.assignments[k].second);
    std::vector<double> numbers;
    for (const auto& c : r.cases)
      if (std::isfinite(c.values_si[k])) numbers.push_back(c.values_si[k]);
    std::string values;
    if (distinct.size() > kListedValues && numbers.size() == r.cases.size()) {
      const auto [lo, hi] = std::minmax_element(numbers.begin(), numbers.end());
      const double largest = std::max(std::abs(*lo), std::abs(*hi));
      values = "from " + valueText(r, *lo, inputUnit(r, k), largest) + " to " + valueText(r, *hi, inputUnit(r, k), largest);
    } else {
      for (std::size_t i = 0; i < std::min(distinct.size(), kListedValues); ++i)
        values += (i ? ", " : "") + distinct[i];
      if (distinct.size() > kListedValues) values += ", ...";
    }
    lines.push_back(fmt::format("{} value{}: {}", distinct.size(), distinct.size() == 1 ? "" : "s", values));
  }
  return lines;
}

io::HtmlReport studyReport(const StudyResults& r, const std::vector<int>& missing) {
  const OutputColumns outputs = splitOutputs(r);
  io::HtmlReport html;
  html.title = "needlesim study: " + r.spec.name;
  html.subtitle = "base scenario " + r.spec.scenario_file.string();
  html.facts.emplace_back("cases", std::to_string(r.cases.size()));
  html.facts.emplace_back("complete", std::to_string(r.cases.size() - missing.size()));
  if (!missing.empty()) {
    std::string m;
    for (int i : missing) m += (m.empty() ? "" : ", ") + std::to_string(i);
    html.facts.emplace_back("to rerun (needlesim sweep --resume)", m);
  }
  const std::vector<std::string> lines = inputLines(r);
  for (std::size_t k = 0; k < lines.size(); ++k) html.facts.emplace_back("input (varied): " + inputField(r, k), lines[k]);
  const std::string constant = constantLine(r, outputs);
  if (!constant.empty()) html.facts.emplace_back("constant over all cases", constant.substr(constant.find(": ") + 2));
  html.tables.push_back(caseTable(r, outputs));
  if (r.table.rows() > kMaxReportRows)
    html.notes.push_back(fmt::format("The table lists the first {} of {} cases; study.csv has every case.",
                                     kMaxReportRows, r.table.rows()));
  html.plots = outputPlots(r, outputs);
  html.notes.push_back(
      "Inputs are the fields the study varies, in the order of the study file; outputs are the cases' key results. "
      "Outputs with one value over every complete case are named once above, not tabulated or plotted (study.csv "
      "has every column). One point per case; each case's own folder (cases/case_NNNN) has its summary, time "
      "series and report.");
  return html;
}

std::string studyOverview(const StudyResults& r) {
  const OutputColumns outputs = splitOutputs(r);
  const auto& cols = r.table.columns();
  std::size_t width = 0;
  for (const auto& p : r.spec.parameters) width = std::max(width, p.field.size());
  for (std::size_t c : outputs.varying) width = std::max(width, cols[c].name.size());
  std::string text = "  inputs (varied):\n";
  const std::vector<std::string> lines = inputLines(r);
  for (std::size_t k = 0; k < lines.size(); ++k) text += fmt::format("    {:<{}}  {}\n", inputField(r, k), width, lines[k]);
  if (!outputs.varying.empty()) {
    const std::size_t n = completeCount(r);
    text += fmt::format("  outputs over the {} complete case{} (smallest to largest):\n", n, n == 1 ? "" : "s");
    for (std::size_t c : outputs.varying) {
      std::vector<double> v = completeValues(r, c);
      v.erase(std::remove_if(v.begin(), v.end(), [](double x) { return !std::isfinite(x); }), v.end());
      const auto [lo, hi] = std::minmax_element(v.begin(), v.end());
      text += v.empty() ? fmt::format("    {:<{}}  n/a\n", cols[c].name, width)
                        : fmt::format("    {:<{}}  {} to {}\n", cols[c].name, width,
                                      valueText(r, *lo, cols[c].unit, std::max(std::abs(*lo), std::abs(*hi))),
                                      valueText(r, *hi, cols[c].unit, std::max(std::abs(*lo), std::abs(*hi))));
    }
  }
  const std::string constant = constantLine(r, outputs);
  if (!constant.empty()) text += "  " + constant + "\n";
  return text;
}

}  // namespace needlesim::study
