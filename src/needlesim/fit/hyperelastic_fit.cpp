#include "needlesim/fit/hyperelastic_fit.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <numeric>

#include "needlesim/core/error.hpp"
#include "needlesim/fit/least_squares.hpp"
#include "needlesim/materials/homogeneous.hpp"
#include "needlesim/materials/hyperelastic.hpp"
#include "needlesim/materials/laws/law_unit.hpp"

namespace needlesim::fit {

namespace mat = needlesim::materials;

namespace {

std::string fmtNum(double v) {
  char b[64];
  std::snprintf(b, sizeof b, "%.6g", v);
  return b;
}

bool startsWith(const std::string& s, const char* p) { return s.rfind(p, 0) == 0; }

int lastLine(const std::vector<int>& lines) { return lines.empty() ? 0 : lines.back(); }

// Residual statistics shared by every fit.
void finishStats(FitResult& r, int k) {
  r.n = static_cast<int>(r.data.size());
  double sse = 0, sumAbs = 0, maxAbs = 0, mean = 0;
  for (double d : r.data) mean += d;
  mean /= std::max(1, r.n);
  double sst = 0;
  for (int i = 0; i < r.n; ++i) {
    double e = r.fitted[i] - r.data[i];
    sse += e * e;
    sumAbs += std::abs(e);
    maxAbs = std::max(maxAbs, std::abs(e));
    sst += (r.data[i] - mean) * (r.data[i] - mean);
  }
  r.sse = sse;
  r.rmse = std::sqrt(sse / std::max(1, r.n));
  r.meanAbsResidual = sumAbs / std::max(1, r.n);  // seed 000 eq 34, rho_bar
  r.maxAbsResidual = maxAbs;                      // seed 000 eq 34, rho_max
  r.rSquared = sst > 0 ? 1.0 - sse / sst : 1.0;
  r.aicc = aicc(sse, r.n, k);
}

using PDef = mat::FitParamDef;

double toInternal(const PDef& d, double theta) {
  if (d.sign == 0) return theta / d.scale;
  return std::log(std::max(std::abs(theta), 1e-300));
}
double toPhysical(const PDef& d, double p) {
  if (d.sign == 0) return p * d.scale;
  return d.sign * std::exp(std::clamp(p, -700.0, 700.0));
}

// Small-strain slope of the test in units of the initial shear modulus mu0.
double slopeOverMu0(TestMode mode) {
  return mode == TestMode::Uniaxial ? 3.0 : mode == TestMode::Equibiaxial ? 6.0 : 1.0;
}

mat::Hyperelastic buildLaw(const mat::LawUnit& law, const std::vector<double>& th) {
  mat::Hyperelastic h;
  h.kind = law.kind;
  h.bulk = 1.0;  // not used by incompressible responses
  law.fit.fromFit(th, h);
  return h;
}

double modelValue(const mat::LawUnit& law, const mat::Hyperelastic& h, const std::vector<double>& th, double x,
                  StressMeasure m, TestMode mode) {
  if (law.fit.smallStrain)  // small strain, incompressible (E = 3 mu0): E eps, 2 E eps, E/3 gamma
    return slopeOverMu0(mode) / 3.0 * th[0] * (x - 1.0);
  switch (mode) {
    case TestMode::Uniaxial:
      return m == StressMeasure::Cauchy ? mat::uniaxialCauchyIncompressible(h, x)
                                        : mat::uniaxialNominalIncompressible(h, x);
    case TestMode::Equibiaxial: {
      double s = mat::equibiaxialCauchyIncompressible(h, x);
      return m == StressMeasure::Cauchy ? s : s / x;  // nominal = sigma / lambda
    }
    case TestMode::Shear:
      return mat::simpleShearIncompressible(h, x - 1.0);  // nominal = Cauchy in simple shear
  }
  return 0.0;
}

// Columns named for compression hold compression as a positive magnitude (seed 002 eq 10 writes
// lambda = 1 - epsilon): 'compressive strain', 'compressive stress', 'compression' (displacement).
bool namedCompressive(const std::string& name) { return startsWith(name, "compressive") || name == "compression"; }

std::string signedNameOf(const std::string& name) {
  if (name == "compression") return "displacement";
  return startsWith(name, "compressive ") ? name.substr(12) : name;
}

// A column of compressive magnitudes whose largest value is negative holds signed data
// (compression negative): reading it as magnitudes would turn the loaded end into tension.
void refuseSignedCompressiveColumn(const io::CsvData& csv, int column) {
  const auto& v = csv.col(column);
  const auto it = std::max_element(v.begin(), v.end(), [](double a, double b) { return std::abs(a) < std::abs(b); });
  if (it == v.end() || *it >= 0.0) return;
  const auto& c = csv.columns[static_cast<std::size_t>(column)];
  const int line = csv.lines[static_cast<std::size_t>(it - v.begin())];
  throw InputError({csv.file, line, 0}, "column '" + c.name + "'", fmtNum(*it / c.scale) + " " + c.unit,
                   "a column named '" + c.name +
                       "' holds compression as a positive magnitude, but its largest value is negative: "
                       "the data look signed (compression negative)",
                   "positive magnitudes in '" + c.name + "' (a negative value there is read as tension), or the column named '" +
                       signedNameOf(c.name) + "' with --loading compression to take the signs as written");
}

// The factor that makes compression negative: -1 for a column of compressive magnitudes;
// otherwise the sign of the loaded end (the value of largest magnitude) is compression.
// Values of the other sign (noise around zero) keep their sign relative to the curve.
double compressionSign(const std::vector<double>& v, bool magnitudes) {
  if (magnitudes) return -1.0;
  const auto it = std::max_element(v.begin(), v.end(), [](double a, double b) { return std::abs(a) < std::abs(b); });
  return it != v.end() && *it < 0.0 ? 1.0 : -1.0;
}

// Compression (a column named for it, or --loading compression): strain and stress are
// made negative in compression. Columns named for compression hold magnitudes, so a
// negative value there is a tensile point; other columns take the sign of their loaded end.
void applyCompressionSigns(const io::CsvData& csv, int xColumn, int yColumn, Loading loading, std::vector<double>& x,
                           std::vector<double>& y, std::vector<std::string>& notes) {
  const auto named = [&](int c) { return c >= 0 && namedCompressive(csv.columns[static_cast<std::size_t>(c)].name); };
  const bool xNamed = named(xColumn), yNamed = named(yColumn);
  if (loading == Loading::Tension && (xNamed || yNamed)) {
    const auto& c = csv.columns[static_cast<std::size_t>(xNamed ? xColumn : yColumn)];
    throw InputError({csv.file, csv.headerLine, c.headerColumn}, "--loading", "tension",
                     "contradicts the column named '" + c.name + "'",
                     "--loading auto or compression for this file, or columns named '" + signedNameOf(c.name) +
                         "' with signed values");
  }
  if (!(loading == Loading::Compression || xNamed || yNamed)) return;
  for (int c : {xColumn, yColumn})
    if (named(c)) refuseSignedCompressiveColumn(csv, c);
  const double sx = compressionSign(x, xNamed), sy = compressionSign(y, yNamed);
  for (double& v : x) v *= sx;
  for (double& v : y) v *= sy;
  notes.push_back("compression: values in columns named 'compressive ...' or 'compression' are magnitudes "
                  "(a negative one is tension); other columns take the sign of their largest value as compressive");
}

}  // namespace

const FitParam& FitResult::param(const std::string& name) const {
  for (const auto& p : params)
    if (p.name == name) return p;
  throw Error("fit result for '" + law + "' has no parameter " + name);
}

const std::vector<std::string>& hyperelasticFitLaws() { return mat::lawNames(); }

UniaxialData readUniaxial(const io::CsvData& csv, const UniaxialReadOptions& opt) {
  UniaxialData d;
  d.file = csv.file;
  d.lines = csv.lines;
  const std::size_t n = csv.rows();
  std::vector<double> x(n);
  int xColumn = -1, yColumn = -1;  // columns read as strain and stress (for compression)
  d.mode = opt.mode;
  int cg = csv.find({"shear strain", "gamma"});
  if (cg >= 0) d.mode = TestMode::Shear;
  int cs = cg >= 0 ? cg : csv.find({"strain", "engineering strain", "compressive strain", "tensile strain"});
  int cl = csv.find({"stretch", "lambda", "stretch ratio"});
  int cd = csv.find({"displacement", "compression", "deformation"});
  std::string xKind;
  if (cs >= 0) {
    csv.checkDim(cs, units::dim::None, "strain");
    x = csv.col(cs);
    xColumn = cs;
    xKind = cg >= 0 ? "shear strain" : "strain";
  } else if (cl >= 0) {
    csv.checkDim(cl, units::dim::None, "stretch");
    for (std::size_t i = 0; i < n; ++i) x[i] = csv.col(cl)[i] - 1.0;
    xKind = "stretch";
  } else if (cd >= 0) {
    csv.checkDim(cd, units::dim::Length, "displacement");
    if (!(opt.sample.height > 0))
      throw InputError({csv.file, csv.headerLine, csv.columns[cd].headerColumn}, "--height", "",
                       "displacement data need the sample height to compute strain (seed 000 eq 29)",
                       "--height with a length, e.g. --height '18 mm'");
    for (std::size_t i = 0; i < n; ++i) x[i] = csv.col(cd)[i] / opt.sample.height;
    xColumn = cd;
    xKind = "displacement / height";
  } else {
    csv.require({"strain", "stretch", "displacement"}, units::dim::None, "strain, stretch or displacement");
  }
  int cy = csv.find({"shear stress", "stress", "cauchy stress", "true stress", "nominal stress",
                     "engineering stress", "compressive stress", "tensile stress"});
  int cf = csv.find({"force", "load"});
  std::vector<double> y(n);
  if (cy >= 0) {
    csv.checkDim(cy, units::dim::Pressure, "stress");
    y = csv.col(cy);
    const std::string& nm = csv.columns[cy].name;
    if (nm.find("nominal") != std::string::npos || nm.find("engineering") != std::string::npos)
      d.measure = StressMeasure::Nominal;
    else if (nm.find("cauchy") != std::string::npos || nm.find("true") != std::string::npos ||
             nm == "shear stress")
      d.measure = StressMeasure::Cauchy;
    else {
      d.measure = opt.plainStress;
      d.notes.push_back(std::string("column '") + nm + "' read as " +
                        (d.measure == StressMeasure::Cauchy ? "Cauchy (true) stress, as the seeds' closed forms"
                                                            : "nominal stress"));
    }
    yColumn = cy;
  } else if (cf >= 0) {
    csv.checkDim(cf, units::dim::Force, "force");
    double A = opt.sample.area > 0 ? opt.sample.area
                                   : (opt.sample.diameter > 0 ? std::numbers::pi / 4 * opt.sample.diameter * opt.sample.diameter : 0);
    if (!(A > 0))
      throw InputError({csv.file, csv.headerLine, csv.columns[cf].headerColumn}, "--area", "",
                       "force data need the sample cross-section to compute stress (seed 000 eq 30)",
                       "--area '900 mm^2' or --diameter '6.34 mm'");
    for (std::size_t i = 0; i < n; ++i) y[i] = csv.col(cf)[i] / A;
    d.measure = StressMeasure::Nominal;
    d.notes.push_back("force / undeformed area read as nominal stress");
  } else {
    csv.require({"stress", "force"}, units::dim::Pressure, "stress or force");
  }
  applyCompressionSigns(csv, xColumn, yColumn, opt.loading, x, y, d.notes);
  if (const std::string note = csv.formatNote(); !note.empty()) d.notes.push_back(note);
  d.stretch.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    d.stretch[i] = 1.0 + x[i];
    if (!(d.stretch[i] > 0.0))
      throw InputError({csv.file, csv.lines[i], 0}, xKind, fmtNum(x[i]),
                       "gives a stretch <= 0 (a strain of -100 % or more)", "strains above -1 (stretches above 0)");
  }
  d.stress = y;
  if (std::all_of(y.begin(), y.end(), [](double v) { return v == 0.0; }))
    throw InputError({csv.file, csv.lines.back(), 0}, "stress", "0", "every stress is zero, so there is nothing to fit",
                     "a loading curve with non-zero stress");
  // Loading curves only: the stretch must move away from 1 monotonically.
  if (n >= 2) {
    double dir = d.stretch.back() - d.stretch.front();
    for (std::size_t i = 1; i < n; ++i) {
      double step = d.stretch[i] - d.stretch[i - 1];
      if (!(step * dir > 0))
        throw InputError({csv.file, csv.lines[i], 0}, xKind, fmtNum(x[i]),
                         "the strain is not monotonic (previous row, line " + std::to_string(csv.lines[i - 1]) +
                             ", has " + fmtNum(x[i - 1]) + ")",
                         "a single loading curve with strictly increasing strain magnitude; remove unloading and repeated points");
    }
  }
  return d;
}

double uniaxialModel(const materials::MaterialSpec& spec, double stretch, StressMeasure measure, TestMode mode) {
  const mat::LawUnit& law = mat::lawUnit(spec.law);
  if (law.fit.smallStrain) return modelValue(law, {}, {spec.param(law.params.front().key)}, stretch, measure, mode);
  return modelValue(law, mat::Hyperelastic::fromSpec(spec), {}, stretch, measure, mode);
}

namespace {

// The number of terms a law is fitted with: `terms`, or the law's default when 0.
int checkedTerms(const UniaxialData& data, const mat::LawUnit& law, int terms) {
  const int maxTerms = law.fit.maxTerms;
  if (terms == 0) terms = law.fit.defaultTerms;
  if (terms < 1 || terms > maxTerms) {
    std::string allowed = "1 (or leave it out)";
    if (maxTerms > 1) {
      allowed = "1";
      for (int t = 2; t < maxTerms; ++t) allowed += ", " + std::to_string(t);
      allowed += " or " + std::to_string(maxTerms);
    }
    throw InputError({data.file, 0, 0}, "--terms", std::to_string(terms), "not allowed for law " + law.name, allowed);
  }
  return terms;
}

// The law a fit names; InputError for a name that is no law.
const mat::LawUnit& fittedLaw(const UniaxialData& data, const std::string& law) {
  if (const mat::LawUnit* u = mat::findLawUnit(law)) return *u;
  std::string allowed;
  for (const auto& n : hyperelasticFitLaws()) allowed += n + ", ";
  throw InputError({data.file, 0, 0}, "--law", law, "unknown law for stress-strain data", allowed + "prony, auto");
}

// Robust starting modulus: the initial slope of the first third of the points.
double initialSlope(const UniaxialData& data, double& ymax) {
  const int n = static_cast<int>(data.stretch.size());
  int m = std::max(2, n / 3);
  double num = 0, den = 0;
  ymax = 0;
  for (int i = 0; i < n; ++i) ymax = std::max(ymax, std::abs(data.stress[i]));
  for (int i = 0; i < std::min(m, n); ++i) {
    double e = data.stretch[i] - 1.0;
    num += e * data.stress[i];
    den += e * e;
  }
  double E0 = den > 0 ? num / den : 0.0;
  if (!(E0 > 0)) {
    double emax = std::abs(data.stretch.back() - 1.0);
    E0 = emax > 0 ? ymax / emax : 1.0;
  }
  if (!(E0 > 0)) E0 = 1e3;
  return E0;
}

// The least-squares fit from each of the law's starting points; the lowest
// finite SSE wins (only law, terms, converged, sse and params are set).
FitResult bestOfStarts(const UniaxialData& data, const mat::LawUnit& law, int terms, double mu0, double ymax) {
  const int n = static_cast<int>(data.stretch.size());
  const double sc = ymax > 0 ? ymax : 1.0;
  FitResult best;
  best.sse = std::numeric_limits<double>::infinity();
  bool any = false;
  for (const auto& start : law.fit.starts(terms, mu0)) {
    const std::vector<PDef>& d = start.params;
    const int k = static_cast<int>(d.size());
    if (n < k + 1)
      throw InputError({data.file, lastLine(data.lines), 0}, "data", std::to_string(n) + " points",
                       "too few points to fit " + std::to_string(k) + " parameter(s) of law " + law.name,
                       "at least " + std::to_string(k + 1) + " points");
    LsqProblem prob;
    prob.nParams = k;
    prob.nResiduals = n;
    auto phys = [d](const Eigen::VectorXd& p) {
      Eigen::VectorXd th(p.size());
      for (int i = 0; i < p.size(); ++i) th[i] = toPhysical(d[i], p[i]);
      return th;
    };
    prob.physical = phys;
    prob.residuals = [&, phys](const Eigen::VectorXd& p, Eigen::VectorXd& r) {
      Eigen::VectorXd th = phys(p);
      std::vector<double> tv(th.data(), th.data() + th.size());
      mat::Hyperelastic h = buildLaw(law, tv);
      for (int i = 0; i < n; ++i)
        r[i] = (modelValue(law, h, tv, data.stretch[i], data.measure, data.mode) - data.stress[i]) / sc;
    };
    Eigen::VectorXd p0(k);
    for (int i = 0; i < k; ++i) p0[i] = toInternal(d[i], start.values[i]);
    prob.starts = {p0};
    LsqResult res = solveLeastSquares(prob);
    double sse = res.cost * sc * sc;
    if (!std::isfinite(sse) || sse >= best.sse) continue;
    any = true;
    best = FitResult{};
    best.sse = sse;
    best.law = law.name;
    best.terms = terms;
    best.converged = res.converged;
    for (int i = 0; i < k; ++i) best.params.push_back({d[i].name, d[i].unit, res.theta[i], res.stdErr[i]});
  }
  if (!any) throw SolverError("fit of law " + law.name + " did not produce a finite result from any starting point");
  return best;
}

// The fitted curve, statistics, material block and notes of the winning fit.
void completeHyperelasticFit(FitResult& best, const UniaxialData& data, const mat::LawUnit& law) {
  const int n = static_cast<int>(data.stretch.size());
  std::vector<double> tv;
  for (const auto& p : best.params) tv.push_back(p.value);
  mat::Hyperelastic h = buildLaw(law, tv);
  best.x = data.stretch;
  best.data = data.stress;
  for (int i = 0; i < n; ++i) best.fitted.push_back(modelValue(law, h, tv, data.stretch[i], data.measure, data.mode));
  finishStats(best, static_cast<int>(best.params.size()));
  best.spec.name = "fitted";
  best.spec.law = law.name;
  for (const auto& p : best.params) best.spec.params[p.name] = p.value;
  if (!law.volumetric)
    best.spec.params["nu"] = 0.49;
  best.notes = data.notes;
  if (law.volumetric)
    best.notes.push_back("uniaxial data do not identify the bulk modulus; the material block uses nu = 0.49");
  if (!best.converged) best.notes.push_back("the optimiser stopped before its tolerances were met");
}

}  // namespace

FitResult fitHyperelastic(const UniaxialData& data, const std::string& lawName, int terms) {
  const mat::LawUnit& law = fittedLaw(data, lawName);
  terms = checkedTerms(data, law, terms);
  double ymax = 0;
  const double E0 = initialSlope(data, ymax);
  const double mu0 = E0 / slopeOverMu0(data.mode);
  FitResult best = bestOfStarts(data, law, terms, mu0, ymax);
  completeHyperelasticFit(best, data, law);
  return best;
}

std::vector<FitResult> fitAllLaws(const UniaxialData& data) {
  std::vector<FitResult> out;
  for (const mat::LawUnit* law : mat::lawUnits())
    for (int terms : law->fit.rankedTerms) {
      const int k = static_cast<int>(law->fit.starts(terms, 1.0).front().params.size());
      if (static_cast<int>(data.stretch.size()) < k + 2) continue;
      try {
        out.push_back(fitHyperelastic(data, law->name, terms));
      } catch (const SolverError&) {
      }
    }
  if (out.empty())
    throw InputError({data.file, lastLine(data.lines), 0}, "data", std::to_string(data.stretch.size()) + " points",
                     "too few points to compare laws", "at least 3 points");
  std::stable_sort(out.begin(), out.end(), [](const FitResult& a, const FitResult& b) { return a.aicc < b.aicc; });
  return out;
}

// ---------------- Prony ----------------

RelaxationData readRelaxation(const io::CsvData& csv, const SampleSize& sample) {
  RelaxationData d;
  d.file = csv.file;
  d.lines = csv.lines;
  int ct = csv.require({"time", "t"}, units::dim::Time, "time");
  d.time = csv.col(ct);
  const std::size_t n = csv.rows();
  int cy = csv.find({"stress", "cauchy stress", "nominal stress", "compressive stress", "tensile stress"});
  if (cy >= 0) {
    csv.checkDim(cy, units::dim::Pressure, "stress");
    if (namedCompressive(csv.columns[cy].name)) refuseSignedCompressiveColumn(csv, cy);
    d.stress = csv.col(cy);
  } else {
    int cf = csv.require({"force", "stress"}, units::dim::Force, "force or stress");
    double A = sample.area > 0 ? sample.area : std::numbers::pi / 4 * sample.diameter * sample.diameter;
    if (!(A > 0))
      throw InputError({csv.file, csv.headerLine, csv.columns[cf].headerColumn}, "--area", "",
                       "force data need the sample cross-section", "--area '900 mm^2' or --diameter '30 mm'");
    for (double f : csv.col(cf)) d.stress.push_back(f / A);
  }
  if (std::all_of(d.stress.begin(), d.stress.end(), [](double v) { return v == 0.0; }))
    throw InputError({csv.file, csv.lines.back(), 0}, "stress", "0", "every stress is zero, so there is nothing to fit",
                     "a relaxation record with non-zero stress");
  for (std::size_t i = 1; i < n; ++i)
    if (!(d.time[i] > d.time[i - 1]))
      throw InputError({csv.file, csv.lines[i], 0}, "time", fmtNum(d.time[i]),
                       "time is not increasing (line " + std::to_string(csv.lines[i - 1]) + " has " +
                           fmtNum(d.time[i - 1]) + " s)",
                       "strictly increasing times");
  const double t0 = d.time.front();
  for (auto& t : d.time) t -= t0;
  std::size_t iEnd = 0;
  int cs = csv.find({"strain", "compressive strain", "stretch", "displacement"});
  if (cs >= 0) {
    if (namedCompressive(csv.columns[cs].name)) refuseSignedCompressiveColumn(csv, cs);
    const auto& s = csv.col(cs);
    double ref = csv.columns[cs].name == "stretch" ? 1.0 : 0.0;
    double mx = 0;
    for (double v : s) mx = std::max(mx, std::abs(v - ref));
    while (iEnd + 1 < n && std::abs(s[iEnd] - ref) < (1 - 1e-9) * mx) ++iEnd;
    d.notes.push_back("ramp end taken where the strain first reaches its maximum");
  } else {
    double mx = 0;
    for (std::size_t i = 0; i < n; ++i)
      if (std::abs(d.stress[i]) > mx) {
        mx = std::abs(d.stress[i]);
        iEnd = i;
      }
    d.notes.push_back("no strain column: ramp end taken at the peak stress");
  }
  if (const std::string note = csv.formatNote(); !note.empty()) d.notes.push_back(note);
  d.rampTime = d.time[iEnd];
  d.holdStart = iEnd;
  return d;
}

namespace {

// The Prony series with the number of terms AICc prefers: a term must earn its keep (AICc drop > 2).
FitResult fitPronyByAicc(const RelaxationData& data, int nHold) {
  FitResult best;
  bool have = false;
  for (int N = 1; N <= 5 && nHold >= 2 * N + 3; ++N) {
    FitResult r = fitProny(data, N);
    if (!have || r.aicc < best.aicc - 2.0) {
      best = r;
      have = true;
    } else {
      break;
    }
  }
  if (!have)
    throw InputError({data.file, lastLine(data.lines), 0}, "data", std::to_string(nHold) + " hold points",
                     "too few points in the hold phase for a Prony series", "at least 5 points after the ramp");
  best.notes.push_back("number of terms chosen by AICc: " + std::to_string(best.terms));
  return best;
}

mat::Prony pronyOf(const Eigen::VectorXd& th, int terms) {
  mat::Prony pr;
  for (int i = 0; i < terms; ++i) pr.terms.push_back({th[1 + 2 * i], th[2 + 2 * i]});
  return pr;
}

// Starts: tau spread log-uniformly over the record; total relaxation from the data.
std::vector<Eigen::VectorXd> pronyStarts(const RelaxationData& data, int terms, double peak, double last) {
  const int k = 2 * terms + 1;
  const double tr = data.rampTime;
  const double tEnd = data.time.back();
  double tFirst = std::max(1e-3 * tEnd, data.time.size() > data.holdStart + 1
                                            ? data.time[data.holdStart + 1] - tr
                                            : 1e-3 * tEnd);
  double gTot = std::clamp(1.0 - last / peak, 0.05, 0.95);
  std::vector<Eigen::VectorXd> starts;
  for (double shift : {1.0, 0.3, 3.0}) {
    Eigen::VectorXd p0(k);
    p0[0] = std::log(std::abs(peak) * 1.05 + 1e-300);
    double gEach = gTot / terms;
    for (int i = 0; i < terms; ++i) {
      double g = gEach;
      p0[1 + i] = std::log(g / (1.0 - gTot));
      double f = terms == 1 ? 0.5 : static_cast<double>(i) / (terms - 1);
      double tau = std::exp(std::log(tFirst) + f * (std::log(tEnd / 3) - std::log(tFirst))) * shift;
      p0[1 + terms + i] = std::log(std::max(tau, 1e-9));
    }
    starts.push_back(p0);
  }
  return starts;
}

// The fit result of a solved Prony problem: parameters, curve over the hold, statistics, notes.
FitResult pronyResult(const RelaxationData& data, int terms, const LsqResult& res) {
  const int nHold = static_cast<int>(data.time.size() - data.holdStart);
  const double tr = data.rampTime;
  FitResult out;
  out.law = "prony";
  out.terms = terms;
  out.converged = res.converged;
  out.params.push_back({"sigma0", "Pa", res.theta[0], res.stdErr[0]});
  for (int i = 0; i < terms; ++i) {
    std::string s = std::to_string(i + 1);
    out.params.push_back({"g" + s, "1", res.theta[1 + 2 * i], res.stdErr[1 + 2 * i]});
    out.params.push_back({"tau" + s, "s", res.theta[2 + 2 * i], res.stdErr[2 + 2 * i]});
  }
  mat::Prony pr = pronyOf(res.theta, terms);
  for (int i = 0; i < nHold; ++i) {
    std::size_t j = data.holdStart + i;
    out.x.push_back(data.time[j]);
    out.data.push_back(data.stress[j]);
    out.fitted.push_back(mat::rampRelaxationClosedForm(pr, res.theta[0], tr, data.time[j]));
  }
  finishStats(out, 2 * terms + 1);
  out.spec.name = "fitted";
  out.spec.law = "";
  out.spec.prony.clear();
  for (const auto& t : pr.terms) out.spec.prony.push_back(t);
  out.notes = data.notes;
  out.notes.push_back("ramp time " + fmtNum(tr) + " s; the elastic stress is taken as linear in time during the ramp");
  if (!out.converged) out.notes.push_back("the optimiser stopped before its tolerances were met");
  return out;
}

}  // namespace

FitResult fitProny(const RelaxationData& data, int terms) {
  const int nHold = static_cast<int>(data.time.size() - data.holdStart);
  if (terms < 0 || terms > 5)
    throw InputError({data.file, 0, 0}, "--terms", std::to_string(terms), "not allowed for a Prony series",
                     "1 to 5, or leave it out to choose by AICc");
  if (terms == 0) return fitPronyByAicc(data, nHold);
  const int k = 2 * terms + 1;
  if (nHold < k + 1)
    throw InputError({data.file, lastLine(data.lines), 0}, "data", std::to_string(nHold) + " hold points",
                     "too few points after the ramp to fit " + std::to_string(k) + " Prony parameters",
                     "at least " + std::to_string(k + 1) + " points in the hold phase");
  const double tr = data.rampTime;
  double peak = data.stress[data.holdStart], last = data.stress.back();
  double sgn = peak >= 0 ? 1.0 : -1.0;
  double ymax = 0;
  for (std::size_t i = data.holdStart; i < data.time.size(); ++i) ymax = std::max(ymax, std::abs(data.stress[i]));
  const double sc = ymax > 0 ? ymax : 1.0;
  // internal p = [log|sigma0|, q_1..q_N (g_i = e^q_i / (1 + sum e^q)), log tau_1..N]
  auto physical = [terms, sgn](const Eigen::VectorXd& p) {
    Eigen::VectorXd th(2 * terms + 1);
    th[0] = sgn * std::exp(p[0]);
    double den = 1.0;
    for (int i = 0; i < terms; ++i) den += std::exp(std::clamp(p[1 + i], -700.0, 700.0));
    for (int i = 0; i < terms; ++i) {
      th[1 + 2 * i] = std::exp(std::clamp(p[1 + i], -700.0, 700.0)) / den;
      th[2 + 2 * i] = std::exp(std::clamp(p[1 + terms + i], -700.0, 700.0));
    }
    return th;
  };
  LsqProblem prob;
  prob.nParams = k;
  prob.nResiduals = nHold;
  prob.physical = physical;
  prob.residuals = [&](const Eigen::VectorXd& p, Eigen::VectorXd& r) {
    Eigen::VectorXd th = physical(p);
    mat::Prony pr = pronyOf(th, terms);
    for (int i = 0; i < nHold; ++i) {
      std::size_t j = data.holdStart + i;
      r[i] = (mat::rampRelaxationClosedForm(pr, th[0], tr, data.time[j]) - data.stress[j]) / sc;
    }
  };
  prob.starts = pronyStarts(data, terms, peak, last);
  return pronyResult(data, terms, solveLeastSquares(prob));
}

}  // namespace needlesim::fit
