// `needlesim fit DATA.csv --law LAW`: tissue characterisation. Parses the
// arguments; the analyses live in src/needlesim/fit (fit_command.hpp).
#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <memory>

#include "commands.hpp"
#include "needlesim/core/error.hpp"
#include "needlesim/fit/fit_command.hpp"

namespace {

struct FitArgs {
  std::vector<std::string> data;
  std::string law, out, loading = "auto", mode = "uniaxial", stress = "cauchy", cutting = "per-speed";
  std::string height, area, diameter, needleDiameter, thickness, windowStart, windowLength, deltaC, speed;
  int terms = 0;
  double dropFraction = 0.2;
  bool overwrite = false, literal = false;
};

}  // namespace

void registerFitCommand(CLI::App& app) {
  auto a = std::make_shared<FitArgs>();
  auto* cmd = app.add_subcommand("fit", "Fit tissue parameters to measured data (stress-strain, relaxation, insertion logs)");
  // DATA and --law are checked in runFit, so a missing one is an InputError (exit 2) listing what is allowed.
  cmd->add_option("data", a->data, "CSV data file(s) with a header 'name [unit], ...'");
  cmd->add_option("--law", a->law, needlesim::fit::fitAnalysesList());
  cmd->add_option("--terms", a->terms, "Yeoh/Ogden terms (1-3) or Prony terms (1-5; default: chosen by AICc)");
  cmd->add_option("-o,--out", a->out,
                  "results folder (default: results/fit_<data file stems>_<law>, with -2, -3 ... if taken)");
  cmd->add_flag("--overwrite", a->overwrite,
                "replace an existing needlesim results folder at --out once the new one is complete (nothing else "
                "is deleted)");
  cmd->add_option("--loading", a->loading,
                  "auto, compression (each column's largest value is compressive) or tension; "
                  "columns named 'compressive ...' hold positive magnitudes");
  cmd->add_option("--mode", a->mode, "homogeneous test: uniaxial (default), equibiaxial or shear");
  cmd->add_option("--stress", a->stress, "measure of a column named plainly 'stress': cauchy (seed convention) or nominal");
  cmd->add_option("--height", a->height, "sample height, for displacement data and K_T (e.g. '7.31 mm')");
  cmd->add_option("--area", a->area, "sample cross-section, for force data (e.g. '900 mm^2')");
  cmd->add_option("--diameter", a->diameter, "sample diameter, for force data and K_T (e.g. '6.34 mm')");
  cmd->add_option("--needle-diameter", a->needleDiameter, "needle diameter for G_c (e.g. '0.71 mm' or '22 G')");
  cmd->add_option("--thickness", a->thickness, "tissue thickness L2 / contact length (e.g. '55 mm')");
  cmd->add_option("--window-start", a->windowStart, "start of the L1 window for G_c (default: puncture depth)");
  cmd->add_option("--window-length", a->windowLength, "L1 for G_c (default: up to the exit)");
  cmd->add_flag("--literal-eq12", a->literal, "G_c with F2' = F2 L1/L2 held constant (literal seed 004 eq 12)");
  cmd->add_option("--delta-c", a->deltaC, "cohesive opening for t_c = 2 G_c/delta_c (seed 004: '0.71 mm')");
  cmd->add_option("--speed", a->speed, "insertion speed of every log (e.g. '3 mm/s'; default: from the data)");
  cmd->add_option("--cutting", a->cutting, "cutting force model for friction: per-speed, constant or linear");
  cmd->add_option("--drop", a->dropFraction, "puncture: relative force drop that marks it (default 0.2)");
  cmd->callback([a] {
    using namespace needlesim;
    namespace u = units::dim;
    fit::FitRequest rq;
    for (const auto& d : a->data) rq.data.emplace_back(d);
    rq.law = a->law;
    rq.terms = a->terms;
    rq.out = a->out;
    rq.overwrite = a->overwrite;
    auto bad = [](const char* opt, const std::string& v, const char* allowed) {
      return InputError({"command line", 0, 0}, opt, v, "not an allowed value", allowed);
    };
    if (a->loading == "auto") rq.uniaxial.loading = fit::Loading::Auto;
    else if (a->loading == "compression") rq.uniaxial.loading = fit::Loading::Compression;
    else if (a->loading == "tension") rq.uniaxial.loading = fit::Loading::Tension;
    else throw bad("--loading", a->loading, "auto, compression, tension");
    if (a->mode == "uniaxial") rq.uniaxial.mode = fit::TestMode::Uniaxial;
    else if (a->mode == "equibiaxial") rq.uniaxial.mode = fit::TestMode::Equibiaxial;
    else if (a->mode == "shear") rq.uniaxial.mode = fit::TestMode::Shear;
    else throw bad("--mode", a->mode, "uniaxial, equibiaxial, shear");
    if (a->stress == "cauchy") rq.uniaxial.plainStress = fit::StressMeasure::Cauchy;
    else if (a->stress == "nominal") rq.uniaxial.plainStress = fit::StressMeasure::Nominal;
    else throw bad("--stress", a->stress, "cauchy, nominal");
    if (a->cutting == "per-speed") rq.cutting = fit::CuttingModel::PerSpeed;
    else if (a->cutting == "constant") rq.cutting = fit::CuttingModel::Constant;
    else if (a->cutting == "linear") rq.cutting = fit::CuttingModel::Linear;
    else throw bad("--cutting", a->cutting, "per-speed, constant, linear");
    if (!(a->dropFraction > 0 && a->dropFraction < 1))
      throw bad("--drop", fmt::format("{}", a->dropFraction), "a fraction between 0 and 1");
    auto q = [](const char* opt, const std::string& v, units::Dim d, double fallback) {
      return v.empty() ? fallback : fit::parseQuantityOption(opt, v, d);
    };
    rq.uniaxial.sample.height = q("--height", a->height, u::Length, 0.0);
    rq.uniaxial.sample.area = q("--area", a->area, units::Dim{2, 0, 0, 0}, 0.0);
    rq.uniaxial.sample.diameter = q("--diameter", a->diameter, u::Length, 0.0);
    rq.needleDiameter = q("--needle-diameter", a->needleDiameter, u::Length, 0.0);
    rq.thickness = q("--thickness", a->thickness, u::Length, 0.0);
    rq.windowStart = q("--window-start", a->windowStart, u::Length, -1.0);
    rq.windowLength = q("--window-length", a->windowLength, u::Length, 0.0);
    rq.literalEq12 = a->literal;
    rq.deltaC = q("--delta-c", a->deltaC, u::Length, 0.0);
    rq.speed = q("--speed", a->speed, u::Velocity, 0.0);
    rq.dropFraction = a->dropFraction;
    fit::FitOutcome o = fit::runFit(rq);
    fmt::print("needlesim fit: {} ({})\n{}", a->law, fmt::join(a->data, ", "), o.table);
    fmt::print("results: {}/ (fit.json, report.html)\n", o.outDir.string());
  });
}
