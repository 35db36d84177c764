// api::fit and api::sweep: `needlesim fit` and `needlesim sweep` as calls.
#include <limits>

#include "needlesim/api/translate.hpp"
#include "needlesim/fit/fit_command.hpp"
#include "needlesim/study/study.hpp"

namespace needlesim::api {

namespace {

// fit.json writes null for a number the fit could not estimate.
double numberOrNaN(const nlohmann::json& j, const char* key) {
  return j.contains(key) && j[key].is_number() ? j[key].get<double>() : std::numeric_limits<double>::quiet_NaN();
}

// The fitted parameters of fit.json's "result" (every analysis that fits parameters has them).
std::vector<FitParameter> parametersOf(const nlohmann::json& j) {
  std::vector<FitParameter> out;
  if (!j.contains("result") || !j["result"].contains("parameters")) return out;
  for (const auto& p : j["result"]["parameters"]) {
    out.push_back(FitParameter{p.value("name", ""), numberOrNaN(p, "value"), p.value("unit", ""),
                               numberOrNaN(p, "std_error")});
  }
  return out;
}

std::string lawOf(const nlohmann::json& j, const std::string& requested) {
  if (j.contains("result") && j["result"].contains("law")) return j["result"]["law"].get<std::string>();
  return requested;
}

}  // namespace

FitResults fit(const FitOptions& options) {
  return detail::translated([&] {
    fit::FitRequest rq;
    rq.data = options.data;
    rq.law = options.law;
    rq.needleDiameter = options.needleDiameter;
    rq.thickness = options.thickness;
    rq.out = options.out;
    rq.write = options.write;
    rq.overwrite = options.overwrite;
    const fit::FitOutcome o = fit::runFit(rq);
    FitResults r;
    r.law = lawOf(o.json, options.law);
    r.parameters = parametersOf(o.json);
    r.table = o.table;
    r.materialYaml = o.materialYaml;
    if (options.write) r.folder = o.outDir;
    return r;
  });
}

SweepSummary sweep(const std::filesystem::path& studyFile, const SweepOptions& options) {
  return detail::translated([&] {
    study::StudySpec spec = study::readStudyFile(studyFile);
    if (!options.out.empty()) spec.directory = options.out.string();
    if (options.parallel >= 0) spec.parallel = options.parallel;
    study::SweepOptions so;
    so.progress = options.progress;
    so.resume = options.resume;
    const study::SweepReport rep = study::runSweep(spec, so);
    return SweepSummary{rep.folder, rep.cases, rep.ran, rep.reused, rep.failed};
  });
}

}  // namespace needlesim::api
