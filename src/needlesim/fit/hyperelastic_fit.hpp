#pragma once
// Fitting hyperelastic laws to uniaxial (compression or tension) data with the
// exact incompressible responses of materials/homogeneous.hpp, and Prony
// series to stress-relaxation data. See docs/fitting.md.
#include <string>
#include <vector>

#include "needlesim/io/csv_reader.hpp"
#include "needlesim/materials/material_spec.hpp"

namespace needlesim::fit {

enum class StressMeasure { Cauchy, Nominal };
enum class Loading { Auto, Compression, Tension };
// Homogeneous test: uniaxial (tension or compression), equibiaxial, or simple shear.
enum class TestMode { Uniaxial, Equibiaxial, Shear };

// Homogeneous test data in SI: stretch lambda (compression < 1) and stress
// (compression < 0). For simple shear, stretch holds 1 + gamma and stress the
// shear stress sigma_12.
struct UniaxialData {
  std::string file;
  std::vector<double> stretch, stress;
  std::vector<int> lines;
  StressMeasure measure = StressMeasure::Cauchy;
  TestMode mode = TestMode::Uniaxial;
  std::vector<std::string> notes;  // how the columns were read
};

struct SampleSize {
  double height = 0.0;  // m (needed for displacement data)
  double area = 0.0;    // m^2 (needed for force data; or give diameter)
  double diameter = 0.0;
};

struct UniaxialReadOptions {
  Loading loading = Loading::Auto;
  // Uniaxial unless given, or unless the columns are named "shear strain"/"shear stress".
  TestMode mode = TestMode::Uniaxial;
  SampleSize sample;
  // For a column named plainly "stress": the seeds fit their F/A data to Cauchy
  // closed forms (seed 000 eq 33, seed 002 eq 10), so Cauchy is the default.
  StressMeasure plainStress = StressMeasure::Cauchy;
};

// Reads strain|stretch|displacement against stress|force. Throws InputError
// (file, line, column) for missing columns, non-monotonic strain, a stretch
// <= 0, or missing sample size.
UniaxialData readUniaxial(const io::CsvData& csv, const UniaxialReadOptions& opt);

struct FitParam {
  std::string name;
  std::string unit;  // SI: "Pa", "1", "s"
  double value = 0.0;
  double stdErr = 0.0;  // NaN when not identifiable from the data
};

struct FitResult {
  std::string law;
  int terms = 0;
  std::vector<FitParam> params;
  int n = 0;
  double sse = 0.0, rmse = 0.0;
  double meanAbsResidual = 0.0, maxAbsResidual = 0.0;  // seed 000 eq 34
  double rSquared = 0.0;
  double aicc = 0.0;
  bool converged = false;
  std::vector<double> x, data, fitted;  // x: stretch (hyperelastic) or time (Prony)
  materials::MaterialSpec spec;         // scenario-ready material
  std::vector<std::string> notes;

  const FitParam& param(const std::string& name) const;  // throws if absent
};

// The laws `needlesim fit --law` accepts for stress-strain data: every law of
// the registry (materials/laws/), each with its parameters and starting points.
const std::vector<std::string>& hyperelasticFitLaws();

// Fits one law; terms: 1 to the law's maximum (Yeoh and Ogden 3), 0 = the
// law's default (Yeoh 3, others 1). Throws InputError for an unknown law or
// too few points.
FitResult fitHyperelastic(const UniaxialData& data, const std::string& law, int terms = 0);

// Fits every law and ranks them by AICc (best first).
std::vector<FitResult> fitAllLaws(const UniaxialData& data);

// Model response used by the fits (exposed for tests and synthetic data):
// incompressible uniaxial, equibiaxial (stress in each loaded direction) or
// simple-shear (x = 1 + gamma) response; "linear" is small-strain
// sigma = E eps (uniaxial), 2 E eps (equibiaxial), E/3 gamma (shear).
double uniaxialModel(const materials::MaterialSpec& spec, double stretch, StressMeasure measure,
                     TestMode mode = TestMode::Uniaxial);

// ---- Stress relaxation ----
struct RelaxationData {
  std::string file;
  std::vector<double> time, stress;  // full record, time from the ramp start
  double rampTime = 0.0;             // s, ramp duration (0: step)
  std::size_t holdStart = 0;         // first index of the hold phase
  std::vector<int> lines;
  std::vector<std::string> notes;
};
// Reads time against stress|force (with area), optional strain|stretch to find
// the end of the ramp (else: time of the peak stress).
RelaxationData readRelaxation(const io::CsvData& csv, const SampleSize& sample);
// terms 1-5, or 0 to choose by AICc.
FitResult fitProny(const RelaxationData& data, int terms = 0);

}  // namespace needlesim::fit
