#include "needlesim/engines/explicit/pain_index.hpp"

#include <algorithm>
#include <cmath>

#include "needlesim/core/error.hpp"
#include "needlesim/materials/homogeneous.hpp"

namespace needlesim::explicit_fe {

double needleAnnulusArea(double outerDiameter, double innerDiameter) {
  const double R = 0.5 * outerDiameter, r = 0.5 * innerDiameter;
  return M_PI * (R * R - r * r);  // seed 001 eq 7
}

double painBasicStress(const materials::MaterialSpec& spec, double strain) {
  return std::abs(materials::uniaxialNominalIncompressible(spec, 1.0 - strain));
}

PainIndex painIndex(const std::vector<double>& time, const std::vector<double>& force, double area,
                    double basicStress) {
  if (!(area > 0) || !(basicStress > 0))
    throw Error("pain index: needle area and basic stress must be positive");
  PainIndex p;
  p.area = area;
  p.basicStress = basicStress;
  const std::size_t n = std::min(time.size(), force.size());
  double integral = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    const double s = std::max(force[i], 0.0) / area;  // eq 7
    p.peakStress = std::max(p.peakStress, s);
    if (i > 0) integral += 0.5 * (std::max(force[i - 1], 0.0) + std::max(force[i], 0.0)) * (time[i] - time[i - 1]);
  }
  p.peak = p.peakStress / basicStress;  // eq 8
  const double T = n > 1 ? time[n - 1] - time[0] : 0.0;
  p.mean = T > 0 ? integral / T / area / basicStress : p.peak;
  return p;
}

}  // namespace needlesim::explicit_fe
