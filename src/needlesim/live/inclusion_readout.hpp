#pragma once
// What the trainer shows of the inclusions at a viewer frame: where each one's material has
// moved (the mean displacement of its region, as inclusions.csv) and, for a target, how far the
// needle misses it (results/inclusion_view.hpp), the tip and axis being the end of the frame's
// needle centre line, of the same step as the field.
#include <array>
#include <optional>
#include <vector>

#include "needlesim/needlesim.hpp"

namespace needlesim::live {

struct InclusionReadout {
  std::array<double, 3> centre{};    // m, the displaced centre, tissue frame
  std::optional<double> miss;        // m, tip to that centre (targets only)
  std::optional<double> missFromAxis;  // m, that centre from the needle's axis (targets only)
};

// One per inclusion, in their order. `field`: a surface field (x y z per vertex of the surface
// the inclusions' regions index); `needle`: x y z per point, base to tip.
std::vector<InclusionReadout> inclusionReadouts(const std::vector<api::Inclusion>& inclusions,
                                                const api::SurfaceField& field, const std::vector<double>& needle);

}  // namespace needlesim::live
