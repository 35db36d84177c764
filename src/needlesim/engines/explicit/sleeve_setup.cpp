#include "needlesim/engines/explicit/sleeve_setup.hpp"

#include <algorithm>
#include <cmath>

#include "needlesim/core/error.hpp"
#include "needlesim/engines/explicit/cohesive_sleeve.hpp"

namespace needlesim::explicit_fe {

SleeveMesh sleeveMeshFor(const Scenario& sc, const needle::NeedleShape& shape, double& radius) {
  const auto& ex = sc.model.explicit_fe;
  const auto& t = sc.tissue;
  if (ex.dimension != 3 || !(shape.innerRadius > 0) || shape.tip != TipType::Bevel)
    throw Error("model.explicit.cohesive.seam: sleeve needs a 3d model and a hollow bevel needle");
  if (!ex.element.empty() && ex.element != "hex8")
    throw Error("model.explicit.cohesive.seam: sleeve needs element: hex8 (got " + ex.element + ")");
  if (sc.tissue.geometry)
    throw InputError(sc.where("model.explicit.cohesive.seam"), "model.explicit.cohesive.seam", "sleeve",
                     "builds its own O-grid block and cannot cut an imported geometry", "seam: plane, or tissue.block");
  if (std::abs(sc.insertion.entry_angle - 0.5 * M_PI) > 1e-9)
    throw Error("model.explicit.cohesive.seam: sleeve needs entry_angle 90 deg (the sleeve runs along x)");
  radius = ex.cohesive.sleeve_radius > 0 ? ex.cohesive.sleeve_radius : 0.5 * (shape.radius + shape.innerRadius);
  const double h = ex.element_size, H = ex.max_element_size;
  SleeveMeshSpec sp;
  sp.width = t.width;
  sp.height = t.height;
  sp.axisY = sc.insertion.entry_offset;
  sp.radius = radius;
  sp.perQuarter = std::max(1, static_cast<int>(std::ceil(0.5 * M_PI * radius / h - 1e-9)));
  sp.coreLayers = std::max(1, static_cast<int>(std::ceil((1 - sp.squareRatio) * radius / h - 1e-9)));
  sp.radialSize = h;
  sp.maxSize = std::max(H, h);
  sp.grading = ex.grading;
  const double dmax = std::min(t.length, sc.maxDepth() + 2 * h);
  sp.xs = gradedCoordinates(0.0, t.length, 0.0, std::max(dmax, h), h, H, ex.grading);
  sp.sleeveDepth = dmax;
  return sleeveBlock(sp);
}

double sleeveCoreInBore(ExplicitSolver& s) {
  const auto* c = s.cohesive();
  const auto* nd = s.needle();
  if (!c || !nd) return -1.0;
  const auto& X = s.mesh().X;
  const auto& u = s.displacement();
  const auto& sh = nd->shape;
  const double tolR = 0.05 * (sh.radius - sh.innerRadius);
  auto pos = [&](int n) { return Eigen::Vector3d(X[3 * n] + u[3 * n], X[3 * n + 1] + u[3 * n + 1], X[3 * n + 2] + u[3 * n + 2]); };
  int passed = 0, inBore = 0;
  for (int p = 0; p < c->pairs(); ++p) {
    const int a = c->node(p, 0), b = c->node(p, 1);
    const Eigen::Vector3d ref(X[3 * a], X[3 * a + 1], X[3 * a + 2]);
    const Eigen::Vector3d q = ref - nd->pose.tip;
    const double sRef = q.dot(nd->pose.axis);
    const Eigen::Vector3d lat = q - sRef * nd->pose.axis;
    if (!(lat.norm() > 0)) continue;
    const double rs = lat.norm();
    // passed by the edge and past the ramp (the wall fully between the lips)
    const double ramp = (sh.radius - sh.innerRadius) / std::tan(needle::kLipRampAngle);
    if (!(sleeveEdge(sh, rs, lat.normalized().dot(nd->pose.bevelSide)) - sRef > ramp)) continue;
    if (sRef < -sh.length) continue;
    ++passed;
    auto radial = [&](int n) {
      const Eigen::Vector3d d = pos(n) - nd->pose.tip;
      return (d - d.dot(nd->pose.axis) * nd->pose.axis).norm();
    };
    if (radial(a) <= sh.innerRadius + tolR && radial(b) >= sh.radius - tolR) ++inBore;
  }
  return passed > 0 ? double(inBore) / passed : -1.0;
}

}  // namespace needlesim::explicit_fe
