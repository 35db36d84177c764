#include "needlesim/materials/homogeneous.hpp"

#include <cmath>
#include <string>

#include "needlesim/core/error.hpp"
#include "needlesim/materials/law_energy.hpp"

namespace needlesim::materials {

namespace {

using A1 = detail::Ad2<1>;

void checkStretch(double lambda, const char* what) {
  if (!(lambda > 0.0) || !std::isfinite(lambda))
    throw Error(std::string(what) + ": stretch " + std::to_string(lambda) +
                " is not allowed; the stretch must be > 0 (strain > -1)");
}

// W along a path given invariants as functions of the path variable.
A1 pathEnergy(const Hyperelastic& m, const A1& I1, const A1& I2, const A1* h) {
  return detail::totalEnergy(m, A1(1.0), I1, I2, h);
}

}  // namespace

double uniaxialNominalIncompressible(const Hyperelastic& m, double lambda) {
  checkStretch(lambda, "uniaxial response");
  A1 l = A1::variable(lambda, 0);
  A1 I1 = l * l + 2.0 * inv(l);
  A1 I2 = 2.0 * l + inv(l * l);
  A1 h[3] = {A1(0.0), A1(0.0), A1(0.0)};
  for (std::size_t p = 0; p < m.ogdenAlpha.size() && p < 3; ++p)
    h[p] = pow(l, m.ogdenAlpha[p]) + 2.0 * pow(l, -0.5 * m.ogdenAlpha[p]);
  return pathEnergy(m, I1, I2, h).g[0];
}

double uniaxialNominalIncompressible(const MaterialSpec& spec, double lambda) {
  if (spec.law == "linear") return spec.param("E") * (lambda - 1.0);
  return uniaxialNominalIncompressible(Hyperelastic::fromSpec(spec), lambda);
}

double uniaxialCauchyIncompressible(const Hyperelastic& m, double lambda) {
  return lambda * uniaxialNominalIncompressible(m, lambda);
}

double equibiaxialCauchyIncompressible(const Hyperelastic& m, double lambda) {
  checkStretch(lambda, "equibiaxial response");
  A1 l = A1::variable(lambda, 0);
  A1 l2 = l * l;
  A1 I1 = 2.0 * l2 + inv(l2 * l2);
  A1 I2 = l2 * l2 + 2.0 * inv(l2);
  A1 h[3] = {A1(0.0), A1(0.0), A1(0.0)};
  for (std::size_t p = 0; p < m.ogdenAlpha.size() && p < 3; ++p)
    h[p] = 2.0 * pow(l, m.ogdenAlpha[p]) + pow(l, -2.0 * m.ogdenAlpha[p]);
  return 0.5 * lambda * pathEnergy(m, I1, I2, h).g[0];
}

double simpleShearIncompressible(const Hyperelastic& m, double gamma) {
  if (!std::isfinite(gamma)) throw Error("simple shear: gamma must be finite");
  A1 g = A1::variable(gamma, 0);
  A1 I1 = 3.0 + g * g;
  A1 I2 = 3.0 + g * g;
  // principal stretches s, 1/s, 1 with s = gamma/2 + sqrt(1 + gamma^2/4)
  A1 s = 0.5 * g + sqrt(1.0 + 0.25 * (g * g));
  A1 h[3] = {A1(0.0), A1(0.0), A1(0.0)};
  for (std::size_t p = 0; p < m.ogdenAlpha.size() && p < 3; ++p)
    h[p] = pow(s, m.ogdenAlpha[p]) + pow(s, -m.ogdenAlpha[p]) + 1.0;
  return pathEnergy(m, I1, I2, h).g[0];
}

UniaxialState uniaxialCompressible(const Hyperelastic& m, double lambda) {
  checkStretch(lambda, "uniaxial response");
  auto lateral = [&](double t) {
    Mat3 F = Mat3::Zero();
    F(0, 0) = lambda;
    F(1, 1) = t;
    F(2, 2) = t;
    return evaluate(m, F, false).sigma(1, 1);
  };
  // sigma_22 increases with t; bracket in log t, then Illinois regula falsi.
  double lo = std::log(1.0 / std::sqrt(lambda)), hi = lo;
  double flo = lateral(std::exp(lo)), fhi = flo;
  double step = 0.05;
  for (int k = 0; k < 200 && flo > 0; ++k) {
    hi = lo;
    fhi = flo;
    lo -= step;
    step *= 1.6;
    flo = lateral(std::exp(lo));
  }
  step = 0.05;
  for (int k = 0; k < 200 && fhi < 0; ++k) {
    lo = hi;
    flo = fhi;
    hi += step;
    step *= 1.6;
    fhi = lateral(std::exp(hi));
  }
  if (!(flo <= 0 && fhi >= 0))
    throw SolverError("uniaxial response: no lateral stretch gives zero lateral stress at stretch " +
                      std::to_string(lambda));
  double x = lo;
  int side = 0;
  for (int it = 0; it < 200; ++it) {
    if (fhi == flo) break;
    x = (lo * fhi - hi * flo) / (fhi - flo);
    double fx = lateral(std::exp(x));
    if (std::abs(fx) <= 1e-14 * (std::abs(flo) + std::abs(fhi)) || hi - lo < 1e-15) break;
    if (fx < 0) {
      lo = x;
      flo = fx;
      if (side == -1) fhi *= 0.5;
      side = -1;
    } else {
      hi = x;
      fhi = fx;
      if (side == 1) flo *= 0.5;
      side = 1;
    }
  }
  UniaxialState out;
  out.lateralStretch = std::exp(x);
  Mat3 F = Mat3::Zero();
  F(0, 0) = lambda;
  F(1, 1) = out.lateralStretch;
  F(2, 2) = out.lateralStretch;
  out.cauchy = evaluate(m, F, false).sigma(0, 0);
  // nominal = force / reference area = sigma * t^2
  out.nominal = out.cauchy * out.lateralStretch * out.lateralStretch;
  return out;
}

double simpleShearCompressible(const Hyperelastic& m, double gamma) {
  Mat3 F = Mat3::Identity();
  F(0, 1) = gamma;
  return evaluate(m, F, false).sigma(0, 1);
}

std::vector<double> relaxationAfterRamp(const std::function<double(double)>& elastic,
                                        const Prony& prony, double tRamp,
                                        const std::vector<double>& times, int rampSubsteps) {
  if (!(tRamp >= 0.0)) throw Error("relaxation: ramp time must be >= 0 s");
  PronyState<double> st;
  double t = 0.0;
  double sigma = pronyUpdate(prony, st, elastic(0.0), 0.0);
  std::vector<double> out;
  out.reserve(times.size());
  const double h = rampSubsteps > 0 && tRamp > 0 ? tRamp / rampSubsteps : 0.0;
  auto advanceTo = [&](double target) {
    // substeps inside the ramp; one exact step through the hold
    while (t < target) {
      double next = target;
      if (t < tRamp && h > 0) next = std::min(target, std::min(tRamp, t + h));
      if (t < tRamp && tRamp == 0.0) next = std::min(target, tRamp);
      double se = elastic(std::min(next, tRamp));
      sigma = pronyUpdate(prony, st, se, next - t);
      t = next;
    }
  };
  for (double target : times) {
    if (target < t) throw Error("relaxation: times must be ascending and >= 0");
    advanceTo(target);
    out.push_back(sigma);
  }
  return out;
}

double rampRelaxationClosedForm(const Prony& prony, double peak, double tRamp, double t) {
  // sigma(t) = peak/tRamp int_0^tRamp G(t - s) ds
  if (tRamp <= 0.0) return peak * prony.relaxation(t);
  double s = prony.gInfinity() * tRamp;
  for (const auto& term : prony.terms)
    s += term.g * term.tau * (std::exp(-(t - tRamp) / term.tau) - std::exp(-t / term.tau));
  return peak / tRamp * s;
}

}  // namespace needlesim::materials
