// The inclusions of a trainer frame (inclusion_readout.hpp).
#include "needlesim/live/inclusion_readout.hpp"

#include "needlesim/results/inclusion_view.hpp"

namespace needlesim::live {

std::vector<InclusionReadout> inclusionReadouts(const std::vector<api::Inclusion>& inclusions,
                                                const api::SurfaceField& field, const std::vector<double>& needle) {
  std::vector<InclusionReadout> out;
  out.reserve(inclusions.size());
  for (const api::Inclusion& I : inclusions) {
    const results::InclusionAtStep at =
        results::inclusionAtStep({I.x, I.y, I.z}, I.target, I.region, field.displacement, needle);
    InclusionReadout r;
    r.centre = {at.centre.x(), at.centre.y(), at.centre.z()};
    if (at.miss) {
      r.miss = at.miss->distance;
      r.missFromAxis = at.miss->fromAxis;
    }
    out.push_back(r);
  }
  return out;
}

}  // namespace needlesim::live
