#pragma once
// The lumped insertion-force model of seed 003 section 3.2 (after Okamura et
// al.): base force = pre-puncture stiffness (eq 3.16) + constant cutting
// (eq 3.24) + modified Karnopp friction along the length in contact (eq 3.23,
// per-length as eq 5.1), layer by layer. A small state machine holds which
// layers are punctured, how deep the needle has cut, and the friction held
// while sticking. Engine-neutral: the 2D FE engine uses it for its coupling
// forces. See docs/models/lumped-force.md for every interpretation.
#include <vector>

#include "needlesim/forces/stiffness.hpp"
#include "needlesim/scenario/scenario.hpp"

namespace needlesim::forces {

enum class Phase : int {
  Outside = 0,     // tip not touching the tissue
  Pressing = 1,    // tip indents a layer that it has not punctured yet
  Cutting = 2,     // tip inside a punctured layer, at the cutting front
  Inside = 3,      // tip inside, behind the front (after a retraction) or resting
  Through = 4,     // full penetration: the tip has left the block
};

struct ForceBreakdown {
  double stiffness = 0.0;  // N
  double cutting = 0.0;    // N
  double friction = 0.0;   // N (positive resists insertion)
  double total() const { return stiffness + cutting + friction; }
  double contact_length = 0.0;  // m of shaft inside the tissue
  Phase phase = Phase::Outside;
  int layer = -1;  // layer the tip is in or pressing on (-1: none)
  bool punctured_now = false;  // a puncture happened in this step
};

class LumpedForceModel {
 public:
  LumpedForceModel(const TissueSpec& tissue, const NeedleSpec& needle, double entry_angle,
                   double relaxation_time = 0.0);

  // Advances to tip depth `depth` (along the needle axis) moving at `velocity`
  // over `dt`, and returns the force on the needle base.
  ForceBreakdown step(double depth, double velocity, double dt);
  void reset();

  std::size_t layerCount() const { return layers_.size(); }
  // Path coordinates (along the needle axis) of layer i's entry and exit.
  double layerStart(std::size_t i) const { return layers_[i].start; }
  double layerEnd(std::size_t i) const { return layers_[i].end; }
  double punctureForce(std::size_t i) const { return layers_[i].puncture_force; }
  double punctureDepth(std::size_t i) const { return layers_[i].stiffness.depthAt(layers_[i].puncture_force); }
  const std::vector<double>& punctureDepthsReached() const { return puncture_at_; }

 private:
  struct Layer {
    double start = 0.0, end = 0.0;  // along the needle axis
    double puncture_force = 0.0;
    double cutting_force = 0.0;
    KarnoppFriction friction;  // the lumped model applies the Karnopp law (contact/karnopp.hpp)
    StiffnessLaw stiffness;
    double held = 0.0;  // friction per length held while sticking (N/m)
  };
  std::vector<Layer> layers_;
  double relaxation_time_;
  std::size_t punctured_ = 0;     // layers [0, punctured_) are punctured
  double front_ = 0.0;            // deepest point cut so far (along the axis)
  double held_cutting_ = 0.0;     // cutting force held while resting at the front
  std::vector<double> puncture_at_;  // tip depth at each puncture
};

}  // namespace needlesim::forces
