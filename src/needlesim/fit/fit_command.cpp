#include "needlesim/fit/fit_command.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <stdexcept>

#include "needlesim/core/error.hpp"
#include "needlesim/core/version.hpp"
#include "needlesim/io/atomic_file.hpp"
#include "needlesim/io/csv_reader.hpp"
#include "needlesim/io/html_report.hpp"
#include "needlesim/results/results_folder.hpp"
#include "needlesim/results/display_units.hpp"

namespace needlesim::fit {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

json num(double v) { return std::isfinite(v) ? json(v) : json(nullptr); }

std::string g6(double v) { return std::isfinite(v) ? fmt::format("{:.6g}", v) : std::string("n/a"); }

// A value with its unit, in the unit a scenario file reads best.
std::string withUnit(double v, const std::string& unit) {
  if (unit == "Pa") return std::abs(v) >= 1e3 ? fmt::format("{:.6g} kPa", v / 1e3) : fmt::format("{:.6g} Pa", v);
  if (unit == "1" || unit.empty()) return fmt::format("{:.6g}", v);
  return fmt::format("{:.6g} {}", v, unit);
}

bool isHyperLaw(const std::string& law) {
  const auto& l = hyperelasticFitLaws();
  return std::find(l.begin(), l.end(), law) != l.end();
}

std::string materialYaml(const FitResult& r) {
  if (r.law == "prony") {
    std::string s = "prony: [";
    for (std::size_t i = 0; i < r.spec.prony.size(); ++i)
      s += fmt::format("{}{{g: {:.6g}, tau: {:.6g} s}}", i ? ", " : "", r.spec.prony[i].g, r.spec.prony[i].tau);
    return s + "]   # add to the material section";
  }
  std::string s = "material: {law: " + r.law;
  for (const auto& p : r.params) s += ", " + p.name + ": " + withUnit(p.value, p.unit);
  s += ", nu: 0.49}";
  return s;
}

json fitJson(const FitResult& r) {
  json j;
  j["law"] = r.law;
  j["terms"] = r.terms;
  j["converged"] = r.converged;
  json ps = json::array();
  for (const auto& p : r.params)
    ps.push_back({{"name", p.name}, {"value", num(p.value)}, {"unit", p.unit}, {"std_error", num(p.stdErr)}});
  j["parameters"] = ps;
  j["statistics"] = {{"n", r.n},
                     {"sse", num(r.sse)},
                     {"rmse", num(r.rmse)},
                     {"mean_abs_residual", num(r.meanAbsResidual)},
                     {"max_abs_residual", num(r.maxAbsResidual)},
                     {"r_squared", num(r.rSquared)},
                     {"aicc", num(r.aicc)}};
  json res = json::array();
  for (std::size_t i = 0; i < r.data.size(); ++i) res.push_back(num(r.fitted[i] - r.data[i]));
  j["residuals"] = res;
  j["material_yaml"] = materialYaml(r);
  j["notes"] = r.notes;
  return j;
}

std::string paramTable(const FitResult& r) {
  std::string t = fmt::format("  {:<10} {:>14} {:>14}  {}\n", "parameter", "value", "std. error", "unit");
  for (const auto& p : r.params)
    t += fmt::format("  {:<10} {:>14} {:>14}  {}\n", p.name, g6(p.value), g6(p.stdErr), p.unit);
  // residuals of stress, all three in the unit that reads the largest
  const auto stress = [&](double v) {
    return results::shownText(v, "Pa", units::DisplayUnits{}, "{:.6g}", std::abs(r.maxAbsResidual));
  };
  t += fmt::format("  n = {}, RMSE = {}, mean |res| = {}, max |res| = {} (seed 000 eq 34), R^2 = {:.5f}, AICc = {:.2f}\n",
                   r.n, stress(r.rmse), stress(r.meanAbsResidual), stress(r.maxAbsResidual), r.rSquared, r.aicc);
  return t;
}

io::Plot curvePlot(const std::vector<FitResult>& fits, bool prony) {
  io::Plot p;
  const auto& f0 = fits.front();
  p.title = prony ? "Relaxation: data and Prony fit" : "Uniaxial response: data and fit";
  p.xlabel = prony ? "time [s]" : "stretch [1]";
  p.ylabel = prony ? "stress [kPa]" : "stress [kPa]";
  p.logx = prony;
  io::PlotSeries d{"data", f0.x, {}, true, false};
  for (double v : f0.data) d.y.push_back(v / 1e3);
  p.series.push_back(d);
  for (std::size_t k = 0; k < fits.size() && k < 8; ++k) {
    const auto& f = fits[k];
    io::PlotSeries s{f.law + (f.terms > 1 ? fmt::format(" ({} terms)", f.terms) : ""), f.x, {}, false, k > 0};
    for (double v : f.fitted) s.y.push_back(v / 1e3);
    p.series.push_back(s);
  }
  return p;
}

io::Plot residualPlot(const FitResult& f, bool prony) {
  io::Plot p;
  p.title = "Residuals (fit - data)";
  p.xlabel = prony ? "time [s]" : "stretch [1]";
  p.ylabel = "residual [kPa]";
  p.logx = prony;
  io::PlotSeries s{"residual", f.x, {}, true, false};
  for (std::size_t i = 0; i < f.data.size(); ++i) s.y.push_back((f.fitted[i] - f.data[i]) / 1e3);
  p.series.push_back(s);
  return p;
}

// A data file's stem as a part of a folder name: letters, digits, '.', '-', '_'
// and UTF-8 bytes stay, anything else (spaces, '+', ',') becomes '_'.
std::string folderNamePart(const fs::path& file) {
  std::string stem = file.stem().string();
  for (char& c : stem) {
    const auto b = static_cast<unsigned char>(c);
    if (!(std::isalnum(b) || b >= 0x80 || c == '.' || c == '-' || c == '_')) c = '_';
  }
  return stem;
}

// `text` cut to at most `n` bytes without splitting a UTF-8 character.
std::string cutUtf8(const std::string& text, std::size_t n) {
  if (text.size() <= n) return text;
  while (n > 0 && (static_cast<unsigned char>(text[n]) & 0xC0) == 0x80) --n;
  return text.substr(0, n);
}

// 8 hex digits of FNV-1a (64 bit) of `text`: stable across runs and machines.
std::string shortHash(const std::string& text) {
  std::uint64_t h = 14695981039346656037ull;
  for (char c : text) {
    h ^= static_cast<unsigned char>(c);
    h *= 1099511628211ull;
  }
  return fmt::format("{:08x}", static_cast<std::uint32_t>(h ^ (h >> 32)));
}

// The stems joined by '+', bounded by kMaxFitNameStems (fitResultsName).
std::string joinedStems(const std::vector<fs::path>& data) {
  std::vector<std::string> stems;
  std::string all;
  for (const auto& d : data) {
    stems.push_back(folderNamePart(d));
    all += (all.empty() ? "" : "+") + stems.back();
  }
  if (all.size() <= kMaxFitNameStems) return all;
  std::string kept = cutUtf8(stems.front(), kMaxFitNameStems);
  std::size_t n = 1;
  while (n < stems.size() && kept.size() + 1 + stems[n].size() <= kMaxFitNameStems) kept += "+" + stems[n++];
  if (n < stems.size()) kept += fmt::format("+{}_more", stems.size() - n);
  return kept + "-" + shortHash(all);
}

// The checked results folder of a fit (before the analysis runs): --out, or
// results/<fitResultsName> with the first free -2, -3 ...
fs::path fitTarget(const FitRequest& rq) {
  if (!rq.out.empty())
    return io::resolveResultsTarget(io::outputPath(rq.out, "--out", commandLine()), "--out", commandLine(),
                                    rq.overwrite);
  return io::resolveResultsTarget(fs::path("results") / fitResultsName(rq.data, rq.law), "", commandLine(), false);
}

// fit.json and report.html, staged beside `target` and moved into place when
// both are written; a staging folder left by a failed write is removed.
void writeFitFolder(const fs::path& target, bool overwrite, const json& j, const io::HtmlReport& rep) {
  io::removeStaleStages(target.parent_path().empty() ? fs::path(".") : target.parent_path());
  io::checkReplaceable(target, overwrite);
  const fs::path stage = io::stagingFolder(target);
  try {
    fs::create_directories(stage);
    io::writeFileAtomic(stage / "fit.json", j.dump(2) + "\n");
    io::writeFileAtomic(stage / "report.html", rep.render());
    io::moveStageIntoPlace(stage, target);
  } catch (...) {
    std::error_code ec;
    fs::remove_all(stage, ec);
    throw;
  }
}

io::CsvData readOne(const FitRequest& rq) {
  if (rq.data.size() != 1)
    throw InputError({}, "DATA", std::to_string(rq.data.size()) + " files",
                     "analysis '" + rq.law + "' reads exactly one data file", "one CSV file");
  return io::readCsv(rq.data.front());
}


// What a fit writes: fit.json, the report, the terminal table and the scenario block.
struct FitParts {
  json j;
  io::HtmlReport rep;
  std::string table;
  std::string materialYaml;
};

void checkFitRequest(const FitRequest& rq) {
  const auto& all = fitAnalyses();
  if (rq.law.empty())
    throw InputError({"command line", 0, 0}, "--law", "", "is missing: say which law to fit or analysis to run",
                     "--law with one of " + fitAnalysesList());
  if (std::find(all.begin(), all.end(), rq.law) == all.end())
    throw InputError({"command line", 0, 0}, "--law", rq.law, "unknown law or analysis", fitAnalysesList());
  if (rq.data.empty()) throw InputError({"command line", 0, 0}, "DATA", "", "no data file given", "one or more CSV files");
}

void startParts(const FitRequest& rq, FitParts& f) {
  f.j["tool"] = "needlesim fit";
  f.j["needlesim"] = {{"version", kVersion}, {"git_revision", kGitRevision}};
  f.j["status"] = "complete";
  f.j["analysis"] = rq.law;
  f.j["data"] = json::array();
  for (const auto& d : rq.data) f.j["data"].push_back(d.string());
  f.rep.title = "needlesim fit: " + rq.law;
  for (const auto& d : rq.data) f.rep.subtitle += (f.rep.subtitle.empty() ? "" : ", ") + d.filename().string();
}

// --law auto: every law ranked by AICc.
void addRanking(const std::vector<FitResult>& fits, FitParts& f) {
  json rk = json::array();
  f.table += fmt::format("  {:<4} {:<18} {:>12} {:>12} {:>12}\n", "rank", "law", "AICc", "RMSE [Pa]", "max|res| [Pa]");
  for (std::size_t k = 0; k < fits.size(); ++k) {
    rk.push_back(fitJson(fits[k]));
    f.table += fmt::format("  {:<4} {:<18} {:>12.2f} {:>12} {:>12}\n", k + 1,
                           fits[k].law + (fits[k].terms > 1 ? fmt::format(" ({})", fits[k].terms) : ""),
                           fits[k].aicc, g6(fits[k].rmse), g6(fits[k].maxAbsResidual));
  }
  f.j["ranking"] = rk;
  f.table += "best: " + fits.front().law + "\n";
}

// --law stiffness: K_T from the neo-Hookean C10 and from the linear E (seed 002 eqs 11, 13).
void addInteractionStiffness(const FitRequest& rq, const std::vector<FitResult>& fits, FitParts& f) {
  const auto& s = rq.uniaxial.sample;
  if (!(s.diameter > 0) || !(s.height > 0))
    throw InputError({"command line", 0, 0}, "--diameter/--height", "",
                     "K_T (seed 002 eq 13) needs the sample diameter and height", "--diameter '6.34 mm' --height '7.31 mm'");
  double C10 = fits.front().param("C10").value, ET = fits[1].param("E").value;
  double KT = interactionStiffness(C10, s.diameter, s.height);
  double KTE = interactionStiffnessFromModulus(ET, s.diameter, s.height);
  f.j["interaction"] = {{"K_T", KT}, {"K_T_from_linear_E", KTE}, {"C10", C10}, {"E_T", ET}, {"unit", "N/m^2"}};
  f.table += fmt::format("  K_T = 3/2 C10 d/h = {} N/m^2 (seed 002 eq 13); from the linear fit E_T = {} Pa: {} N/m^2 (eq 11)\n",
                         g6(KT), g6(ET), g6(KTE));
  f.materialYaml = fmt::format("interaction: {{K_T: {:.6g} N/m^2}}", KT);
  f.rep.facts.push_back({"K_T (eq 13)", g6(KT) + " N/m^2"});
}

// A hyperelastic law, --law auto or --law stiffness on one stress-strain file.
void runStressStrainFit(const FitRequest& rq, FitParts& f) {
  io::CsvData csv = readOne(rq);
  UniaxialData data = readUniaxial(csv, rq.uniaxial);
  std::vector<FitResult> fits;
  if (rq.law == "auto") {
    fits = fitAllLaws(data);
  } else if (rq.law == "stiffness") {
    fits.push_back(fitHyperelastic(data, "neo-hookean"));
    fits.push_back(fitHyperelastic(data, "linear"));
  } else {
    fits.push_back(fitHyperelastic(data, rq.law, rq.terms));
  }
  const FitResult& best = fits.front();
  f.j["measure"] = data.measure == StressMeasure::Cauchy ? "cauchy" : "nominal";
  f.j["result"] = fitJson(best);
  f.materialYaml = materialYaml(best);
  if (rq.law == "auto") addRanking(fits, f);
  f.table += paramTable(best);
  if (rq.law == "stiffness") addInteractionStiffness(rq, fits, f);
  for (const auto& p : best.params) f.rep.facts.push_back({p.name, g6(p.value) + " ± " + g6(p.stdErr) + " " + p.unit});
  f.rep.facts.push_back({"RMSE", g6(best.rmse) + " Pa"});
  f.rep.facts.push_back({"mean / max |residual| (seed 000 eq 34)", g6(best.meanAbsResidual) + " / " + g6(best.maxAbsResidual) + " Pa"});
  f.rep.plots.push_back(curvePlot(fits, false));
  f.rep.plots.push_back(residualPlot(best, false));
  const char* modeName = data.mode == TestMode::Uniaxial ? "uniaxial" : data.mode == TestMode::Equibiaxial ? "equibiaxial" : "simple shear";
  f.j["mode"] = modeName;
  if (data.mode == TestMode::Shear)
    for (auto& p : f.rep.plots) p.xlabel = "1 + shear strain [1]";
  f.rep.subtitle += std::string(" (") + modeName + ")";
  f.rep.notes = best.notes;
}

void runPronyFit(const FitRequest& rq, FitParts& f) {
  io::CsvData csv = readOne(rq);
  RelaxationData data = readRelaxation(csv, rq.uniaxial.sample);
  FitResult r = fitProny(data, rq.terms);
  f.j["result"] = fitJson(r);
  f.materialYaml = materialYaml(r);
  f.table += paramTable(r);
  for (const auto& p : r.params) f.rep.facts.push_back({p.name, g6(p.value) + " ± " + g6(p.stdErr) + " " + p.unit});
  f.rep.plots.push_back(curvePlot({r}, true));
  f.rep.plots.push_back(residualPlot(r, true));
  f.rep.notes = r.notes;
}

io::Plot frictionPlot(const FrictionFit& fr, const std::vector<InsertionLog>& logs) {
  io::Plot p;
  p.title = "Insertion force after puncture: data and fit (seed 003 eq 5.1)";
  p.xlabel = "depth [mm]";
  p.ylabel = "force [N]";
  for (std::size_t r = 0; r < fr.depth.size(); ++r) {
    std::vector<double> zmm;
    for (double z : fr.depth[r]) zmm.push_back(z * 1e3);
    p.series.push_back({fmt::format("data {:.3g} mm/s", logs[r].speed * 1e3), zmm, fr.measured[r], true, false});
    p.series.push_back({fmt::format("fit {:.3g} mm/s", logs[r].speed * 1e3), zmm, fr.fitted[r], false, false});
  }
  return p;
}

// --law friction: summaries (seed 003 eq 5.1 rows) or raw logs.
void runFrictionFit(const FitRequest& rq, FitParts& f) {
  io::CsvData first = io::readCsv(rq.data.front());
  FrictionFit fr;
  if (first.find({"cutting force", "cutting"}) >= 0) {
    if (rq.data.size() != 1) throw InputError({}, "DATA", "", "a summary table is read alone", "one CSV file");
    fr = frictionFromSummaries(readFrictionSummaries(first), first.file);
    f.j["input"] = "summary rows (seed 003 eq 5.1)";
  } else {
    std::vector<InsertionLog> logs;
    for (const auto& d : rq.data) {
      auto l = readInsertionLogs(io::readCsv(d), rq.speed);
      logs.insert(logs.end(), l.begin(), l.end());
    }
    fr = fitFrictionCutting(logs, rq.thickness, rq.cutting);
    f.j["input"] = "insertion logs";
    f.rep.plots.push_back(frictionPlot(fr, logs));
  }
  json cut = json::array();
  for (std::size_t s = 0; s < fr.speeds.size(); ++s)
    cut.push_back({{"speed", fr.speeds[s]}, {"cutting_force", num(fr.cutting[s])}, {"std_error", num(fr.seCutting[s])}});
  f.j["result"] = {{"parameters",
                    {{{"name", "C_p"}, {"value", fr.C}, {"unit", "N/m"}, {"std_error", num(fr.seC)}},
                     {{"name", "b_p"}, {"value", fr.b}, {"unit", "N s/m^2"}, {"std_error", num(fr.seB)}}}},
                   {"cutting", cut},
                   {"statistics", {{"n", fr.n}, {"rmse", fr.rmse}}}};
  f.table += fmt::format("  C_p = {} ± {} N/m, b_p = {} ± {} N s/m^2 (seed 003 eq 5.1, least squares over {} points)\n",
                         g6(fr.C), g6(fr.seC), g6(fr.b), g6(fr.seB), fr.n);
  for (std::size_t s = 0; s < fr.speeds.size(); ++s)
    f.table += fmt::format("  speed {:>8} mm/s: cutting force {} ± {} N\n", g6(fr.speeds[s] * 1e3), g6(fr.cutting[s]),
                           g6(fr.seCutting[s]));
  double meanCut = 0;
  for (double c : fr.cutting) meanCut += c / fr.cutting.size();
  f.materialYaml = fmt::format("friction: {{C_p: {:.6g} N/m, b_p: {:.6g} N s/m^2}}\ncutting: {{force: {:.6g} N}}",
                               fr.C, fr.b, meanCut);
  f.rep.facts = {{"C_p", g6(fr.C) + " ± " + g6(fr.seC) + " N/m"}, {"b_p", g6(fr.b) + " ± " + g6(fr.seB) + " N s/m^2"}};
}

io::Plot insertionPlot(const InsertionLog& log, const Puncture& p) {
  io::Plot pl;
  pl.title = "Insertion force: " + fs::path(log.file).filename().string();
  pl.xlabel = "depth [mm]";
  pl.ylabel = "force [N]";
  std::vector<double> zmm;
  for (double z : log.depth) zmm.push_back(z * 1e3);
  pl.series.push_back({"force", zmm, log.force, false, false});
  if (p.found) pl.series.push_back({"puncture", {p.depth * 1e3}, {p.force}, true, false});
  return pl;
}

// --law toughness on one log: G_c (seed 002 eq 12), with its window drawn on the log's plot.
ToughnessResult addToughness(const FitRequest& rq, const InsertionLog& log, json& run, io::Plot& pl, FitParts& f) {
  ToughnessOptions o;
  o.diameter = rq.needleDiameter;
  o.shaftLength = rq.thickness;
  o.windowStart = rq.windowStart;
  o.windowLength = rq.windowLength;
  o.literalEq12 = rq.literalEq12;
  ToughnessResult t = ruptureToughness(log, o);
  run["toughness"] = {{"G_c", t.Gc}, {"G_ftc", t.Gftc}, {"G_ft", t.Gft}, {"F2", t.F2},
                      {"L1", t.L1}, {"L2", t.L2}, {"window_start", t.windowStart}, {"area", t.area}};
  if (rq.deltaC > 0) run["toughness"]["t_c"] = cohesiveStrength(t.Gc, rq.deltaC);
  f.table += fmt::format("  G_c = {} J/m^2 (G_ftc {} - G_ft {}; L1 = {} mm from {} mm, L2 = {} mm, F2 = {} N){}\n",
                         g6(t.Gc), g6(t.Gftc), g6(t.Gft), g6(t.L1 * 1e3), g6(t.windowStart * 1e3),
                         g6(t.L2 * 1e3), g6(t.F2),
                         rq.deltaC > 0 ? fmt::format("; t_c = 2 G_c/delta_c = {} Pa", g6(cohesiveStrength(t.Gc, rq.deltaC))) : "");
  pl.series.push_back({"L1 window", {t.windowStart * 1e3, (t.windowStart + t.L1) * 1e3}, {0.0, 0.0}, true, false});
  return t;
}

// --law toughness or puncture: every run of every log file.
void runInsertionAnalyses(const FitRequest& rq, FitParts& f) {
  json runs = json::array();
  double sumGc = 0;
  int nGc = 0;
  double sumPf = 0;
  int nP = 0;
  for (const auto& d : rq.data) {
    for (const auto& log : readInsertionLogs(io::readCsv(d), rq.speed)) {
      json run{{"file", log.file}, {"speed", log.speed}};
      Puncture p = detectPuncture(log, rq.dropFraction);
      run["puncture"] = {{"found", p.found}, {"depth", p.depth}, {"force", p.force}, {"drop", p.drop},
                         {"stiffness", p.stiffness}, {"line", p.line}};
      if (p.found) {
        sumPf += p.force;
        ++nP;
        f.table += fmt::format("  {}: puncture at depth {} mm, force {} N (drop {} N, line {})\n", log.file,
                               g6(p.depth * 1e3), g6(p.force), g6(p.drop), p.line);
      } else {
        f.table += fmt::format("  {}: no puncture (no drop by {} % of the peak)\n", log.file, rq.dropFraction * 100);
      }
      io::Plot pl = insertionPlot(log, p);
      if (rq.law == "toughness") {
        sumGc += addToughness(rq, log, run, pl, f).Gc;
        ++nGc;
      }
      f.rep.plots.push_back(pl);
      runs.push_back(run);
    }
  }
  f.j["runs"] = runs;
  if (nGc > 0) {
    f.j["G_c_mean"] = sumGc / nGc;
    f.materialYaml = fmt::format("interaction: {{toughness: {:.6g} N/m}}", sumGc / nGc);
    f.rep.facts.push_back({"G_c (mean)", g6(sumGc / nGc) + " J/m^2"});
  } else if (nP > 0) {
    f.j["puncture_force_mean"] = sumPf / nP;
    f.materialYaml = fmt::format("puncture: {{force: {:.6g} N}}", sumPf / nP);
    f.rep.facts.push_back({"puncture force (mean)", g6(sumPf / nP) + " N"});
  }
}

// The scenario block under "scenario block:", indented, one line per line.
void appendScenarioBlock(const std::string& yaml, std::string& table) {
  if (yaml.empty()) return;
  table += "scenario block:\n";
  std::size_t start = 0;
  while (start < yaml.size()) {
    std::size_t end = yaml.find('\n', start);
    if (end == std::string::npos) end = yaml.size();
    table += "  " + yaml.substr(start, end - start) + "\n";
    start = end + 1;
  }
}

}  // namespace

const std::vector<std::string>& fitAnalyses() {
  static const std::vector<std::string> v = [] {
    std::vector<std::string> a = hyperelasticFitLaws();
    for (const char* other : {"auto", "prony", "toughness", "friction", "puncture", "stiffness"}) a.push_back(other);
    return a;
  }();
  return v;
}

std::string fitAnalysesList() {
  std::string list;
  for (const auto& a : fitAnalyses()) list += (list.empty() ? "" : ", ") + a;
  return list;
}

std::string fitResultsName(const std::vector<fs::path>& data, const std::string& law) {
  return "fit_" + joinedStems(data) + "_" + law;
}

double parseQuantityOption(const std::string& option, const std::string& text, units::Dim dim) {
  units::Quantity q;
  try {
    q = units::parse(text);
  } catch (const std::invalid_argument& e) {
    throw InputError({"command line", 0, 0}, option, text, std::string("not a quantity: ") + e.what(),
                     units::examples(dim));
  }
  if (q.gauge && dim == units::dim::Length) {
    auto g = units::gaugeSize(static_cast<int>(q.value));
    if (!g) throw InputError({"command line", 0, 0}, option, text, "unknown needle gauge", "a gauge from 7 G to 34 G");
    return g->outer;
  }
  if (!(q.dim == dim) || q.gauge)
    throw InputError({"command line", 0, 0}, option, text, "has the wrong unit", units::examples(dim));
  return q.value;
}

FitOutcome runFit(const FitRequest& rq) {
  checkFitRequest(rq);
  FitOutcome out;
  if (rq.write) out.outDir = fitTarget(rq);
  FitParts f;
  startParts(rq, f);
  if (isHyperLaw(rq.law) || rq.law == "auto" || rq.law == "stiffness")
    runStressStrainFit(rq, f);
  else if (rq.law == "prony")
    runPronyFit(rq, f);
  else if (rq.law == "friction")
    runFrictionFit(rq, f);
  else if (rq.law == "toughness" || rq.law == "puncture")
    runInsertionAnalyses(rq, f);
  out.materialYaml = f.materialYaml;
  f.j["material_yaml"] = out.materialYaml;
  appendScenarioBlock(out.materialYaml, f.table);
  out.json = f.j;
  out.table = f.table;
  if (rq.write) writeFitFolder(out.outDir, rq.overwrite, f.j, f.rep);
  return out;
}

}  // namespace needlesim::fit
