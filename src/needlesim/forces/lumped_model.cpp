#include "needlesim/forces/lumped_model.hpp"

#include <algorithm>
#include <cmath>

#include "needlesim/contact/karnopp.hpp"
#include "needlesim/materials/material_spec.hpp"

namespace needlesim::forces {

LumpedForceModel::LumpedForceModel(const TissueSpec& tissue, const NeedleSpec& needle, double entry_angle,
                                   double relaxation_time)
    : relaxation_time_(relaxation_time) {
  // Layer thicknesses are normal to the surface; along a needle entering at
  // angle theta each spans thickness / sin(theta) of path.
  const double stretch = 1.0 / std::sin(entry_angle);
  double s = 0.0;
  for (const auto& L : tissue.layers) {
    Layer l;
    l.start = s;
    l.end = s + L.thickness * stretch;
    s = l.end;
    auto mod = materials::smallStrainModuli(L.material);
    l.stiffness = StiffnessLaw{mod.youngs(), mod.poisson(), needle.bevel_angle, entry_angle};
    // A puncture given as a depth: the stiffness force at that depth.
    l.puncture_force = L.puncture_depth > 0.0 ? l.stiffness.force(L.puncture_depth) : L.puncture_force;
    l.cutting_force = L.cutting_force;
    l.friction = L.friction;
    layers_.push_back(l);
  }
}

void LumpedForceModel::reset() {
  punctured_ = 0;
  front_ = 0.0;
  held_cutting_ = 0.0;
  puncture_at_.clear();
  for (auto& l : layers_) l.held = 0.0;
}

ForceBreakdown LumpedForceModel::step(double depth, double velocity, double dt) {
  ForceBreakdown out;
  if (layers_.empty()) return out;
  const double decay = relaxation_time_ > 0.0 ? std::exp(-dt / relaxation_time_) : 1.0;

  // 1. Puncture: the layer the tip presses on gives way at its threshold.
  //    Several thin layers may go in one step, hence the loop.
  while (punctured_ < layers_.size()) {
    Layer& l = layers_[punctured_];
    double z = depth - l.start;  // indentation of this layer's surface
    if (z <= 0.0) break;
    if (l.stiffness.force(z) < l.puncture_force) break;
    puncture_at_.push_back(depth);
    out.punctured_now = true;
    front_ = std::max(front_, l.start);
    ++punctured_;
  }

  // 2. Where is the tip?
  const double blockEnd = layers_.back().end;
  if (punctured_ < layers_.size() && depth > layers_[punctured_].start) {
    // Pressing on the first layer not yet punctured (eq 3.16); the layers before it cut.
    const Layer& l = layers_[punctured_];
    out.phase = Phase::Pressing;
    out.layer = static_cast<int>(punctured_);
    out.stiffness = l.stiffness.force(depth - l.start);
  } else if (depth >= blockEnd && punctured_ == layers_.size()) {
    out.phase = Phase::Through;
    out.layer = -1;
  } else if (punctured_ > 0 && depth > layers_.front().start) {
    // Inside punctured tissue: find the layer holding the tip.
    std::size_t j = 0;
    while (j + 1 < punctured_ && depth >= layers_[j].end) ++j;
    out.layer = static_cast<int>(j);
    const bool atFront = depth >= front_ - 1e-12;
    const double half = 0.5 * layers_[j].friction.static_band;
    if (atFront && velocity >= half) {
      // Advancing into fresh tissue: constant cutting force (eq 3.24).
      out.phase = Phase::Cutting;
      out.cutting = layers_[j].cutting_force;
      held_cutting_ = out.cutting;
    } else if (atFront && velocity > -half) {
      // Resting at the front: the tissue ahead stays loaded (relaxes with the pause).
      out.phase = Phase::Inside;
      held_cutting_ *= decay;
      out.cutting = held_cutting_;
    } else {
      out.phase = Phase::Inside;
      held_cutting_ = 0.0;
    }
  }
  front_ = std::max(front_, std::min(depth, blockEnd));
  if (out.phase != Phase::Cutting && out.phase != Phase::Inside) held_cutting_ = 0.0;

  // 3. Friction along the shaft in every punctured layer (eq 3.23 x length in contact).
  for (std::size_t i = 0; i < punctured_; ++i) {
    Layer& l = layers_[i];
    double len = std::clamp(std::min(depth, front_), l.start, l.end) - l.start;
    if (len <= 0.0) {
      l.held = 0.0;
      continue;
    }
    l.held *= decay;
    double f = contact::karnoppPerLength(l.friction, velocity, l.held);
    l.held = f;  // while sliding, the tissue carries the dynamic friction; sticking keeps it
    out.friction += f * len;
    out.contact_length += len;
  }
  return out;
}

}  // namespace needlesim::forces
