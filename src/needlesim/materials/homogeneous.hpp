#pragma once
// Homogeneous responses of a law, for fitting and tests. Stretch lambda = 1 +
// engineering strain (compression: lambda < 1). "Cauchy" is the true stress,
// "nominal" the force per undeformed area (first Piola-Kirchhoff).
#include <functional>
#include <vector>

#include "needlesim/materials/hyperelastic.hpp"
#include "needlesim/materials/viscoelastic.hpp"

namespace needlesim::materials {

// Exact incompressible responses (J = 1, volumetric part ignored), from the
// isochoric energy W(lambda) along each path: sigma = lambda dW/dlambda for
// uniaxial F = diag(l, l^-1/2, l^-1/2) (seed 002 eq 10, seed 000 eq 33 for
// neo-Hookean and Fung), sigma = lambda/2 dW/dlambda for equibiaxial
// F = diag(l, l, l^-2), and sigma_12 = dW/dgamma for simple shear.
double uniaxialCauchyIncompressible(const Hyperelastic& law, double lambda);
double uniaxialNominalIncompressible(const Hyperelastic& law, double lambda);
double equibiaxialCauchyIncompressible(const Hyperelastic& law, double lambda);
double simpleShearIncompressible(const Hyperelastic& law, double gamma);
// The nominal stress of a layer's law given as a spec, incompressible uniaxial:
// the exact response above for a hyperelastic law, E (lambda - 1) for
// "linear" (small strain, as the stress-strain fits read it).
double uniaxialNominalIncompressible(const MaterialSpec& spec, double lambda);

// Compressible uniaxial stress: the lateral stretch t is solved so that the
// lateral Cauchy stress vanishes (F = diag(lambda, t, t)).
struct UniaxialState {
  double cauchy = 0.0;
  double nominal = 0.0;
  double lateralStretch = 1.0;
};
UniaxialState uniaxialCompressible(const Hyperelastic& law, double lambda);
// Compressible simple shear, F = I + gamma e1 (x) e2: Cauchy sigma_12.
double simpleShearCompressible(const Hyperelastic& law, double gamma);

// Relaxation after a ramp: a scalar elastic stress history elastic(t) (ramp
// from t = 0 to tRamp, then held) filtered by the Prony series (QLV). The
// result at each requested time (ascending, >= 0) uses the exact update of
// viscoelastic.hpp on substeps of the ramp (rampSubsteps) and exact steps in
// the hold.
std::vector<double> relaxationAfterRamp(const std::function<double(double)>& elastic,
                                        const Prony& prony, double tRamp,
                                        const std::vector<double>& times, int rampSubsteps = 400);

// Closed form for a linear elastic stress ramp (elastic(t) = peak t / tRamp):
// sigma(t) for t >= tRamp, used by tests and the Prony fit.
double rampRelaxationClosedForm(const Prony& prony, double peak, double tRamp, double t);

}  // namespace needlesim::materials
