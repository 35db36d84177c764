#include "needlesim/engines/realtime/tip_forces.hpp"

#include <algorithm>
#include <cmath>

namespace needlesim::realtime {

TipForces::TipForces(std::vector<Membrane> membranes, std::vector<double> path_s, int comps)
    : membranes_(std::move(membranes)), s_(std::move(path_s)), comps_(comps) {}

int TipForces::nearestNode(const std::vector<double>& path_s, double s) {
  int node = 0;
  for (int i = 1; i < static_cast<int>(path_s.size()); ++i)
    if (std::abs(path_s[static_cast<std::size_t>(i)] - s) < std::abs(path_s[static_cast<std::size_t>(node)] - s)) node = i;
  return node;
}

// Phase A: the tip indents the next unpunctured layer boundary (eq 3.16, the layer's
// E and nu) until its puncture threshold; phase B: the load is released and the tissue
// relaxes.
double TipForces::press(double s_tip, Eigen::VectorXd& fK, bool& punctured_now) {
  pressing_ = false;
  while (pending_ < membranes_.size() && s_tip > membranes_[pending_].s) {
    const Membrane& mb = membranes_[pending_];
    const double F1 = mb.law.force(s_tip - mb.s);
    if (F1 < mb.threshold) {
      pressing_ = true;
      fK[comps_ * mb.node] += F1;  // axial load on the boundary node
      return F1;
    }
    punctured_now = true;
    if (pending_ == 0) front_ = s_tip;
    ++pending_;
  }
  return 0.0;
}

double TipForces::reach(double s_tip) const {
  return pressing_ ? std::min(s_tip, membranes_[pending_].s - 1e-9) : s_tip;
}

double TipForces::cut(const AxialMotion& mo, double Fcut, double band, double s_exit, Eigen::VectorXd& fK) {
  const double s_tip = mo.s_tip;
  const bool inside = entered() && !pressing_ && s_tip > 0.0 && s_tip < s_exit;
  double Fc = 0.0;
  if (inside && mo.v_ax > -band && s_tip >= front_ - 1e-9) Fc = Fcut;
  if (entered()) front_ = std::max(front_, std::min(s_tip, s_exit));
  if (!(Fc > 0.0)) return Fc;
  const int P = static_cast<int>(s_.size());
  int k = 0;
  while (k + 1 < P && s_[static_cast<std::size_t>(k + 1)] <= s_tip) ++k;
  if (k + 1 < P) {
    const double s0 = s_[static_cast<std::size_t>(k)], s1 = s_[static_cast<std::size_t>(k + 1)];
    const double w1 = std::clamp((s_tip - s0) / (s1 - s0), 0.0, 1.0);
    fK[comps_ * k] += (1.0 - w1) * Fc;
    fK[comps_ * (k + 1)] += w1 * Fc;
  } else {
    fK[comps_ * k] += Fc;
  }
  return Fc;
}

}  // namespace needlesim::realtime
