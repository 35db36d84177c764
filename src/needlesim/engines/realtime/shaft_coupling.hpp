#pragma once
// The needle shaft's coupling to the tissue path nodes, shared by the real-time engines
// (seed 003 eqs 3.12 and 3.18-3.23, with the modified local constraints of Gao et al. 2016,
// seed 003 ref 16): an Euler-Bernoulli needle clamped at its base (needle/beam_element.hpp
// cantilever influence functions, one per bending plane) tied laterally to the coupled path
// nodes, which stick to it axially or slip with modified Karnopp friction (eq 3.23).
//
// `lateral` bending directions (1 in 2D: n; 2 in 3D: n and b); path load k = comps i + c with
// comps = 1 + lateral, c = 0 axial t, c = 1.. the lateral directions (tissue_dynamics.hpp).
// Per step: couple() the path prefix the tip has passed, measure() the shaft in contact (each
// node's share of it, from the nodes' current order along the axis), then solve() the small SPD system on the coupled nodes (lateral ties + axial stick or implicit
// slip) by an active set on the friction status. Allocation-free after construction.
#include <Eigen/Core>
#include <array>
#include <string>
#include <vector>

#include "needlesim/contact/karnopp.hpp"
#include "needlesim/engines/realtime/tip_forces.hpp"
#include "needlesim/engines/realtime/tissue_dynamics.hpp"
#include "needlesim/scenario/scenario.hpp"

namespace needlesim::realtime {

// Status of the modified Karnopp law (eq 3.23, contact/karnopp.hpp) at one coupled node.
using FrictionStatus = contact::KarnoppState;

// Rigid needle pose relative to the reference axis (entry point, t, lateral directions) and
// the bevel's transverse tip load, per lateral direction j.
struct NeedleLine {
  double sB = 0.0;      // m, base along the reference axis
  double cosphi = 1.0;  // cosine of the needle's tilt from the axis
  std::array<double, 2> dB{}, tanphi{}, Q{};  // m, 1, N
};

struct ShaftSettings {
  std::string engine;
  int lateral = 1;
  double EI = 0.0, length = 0.0;  // N m^2, m
  std::vector<double> path_s;     // m, reference axial position of each path node
  // Per path node (eq 3.23), its static band included; D_p and D_n as given (contact/karnopp.hpp).
  std::vector<KarnoppFriction> friction;
  int max_iterations = 12;
  double entry_s = 0.0;           // m, where the axis enters the tissue (the first node's rubbed length starts there)
  // m/N per path load (comps per point): a compliant interface between the shaft and the tissue point in series
  // with each tie (lateral: on the whole load; axial stick and slip: on the change of the
  // shaft's load since the last step, the interface keeping its stretch); empty = rigid ties.
  std::vector<double> interface_compliance;
};

class ShaftCoupling {
 public:
  ShaftCoupling() = default;
  explicit ShaftCoupling(ShaftSettings s);

  // Known axial tip loads of this step (press, cutting): set before solve().
  Eigen::VectorXd& knownLoads() { return fK_; }
  void setNeedle(const NeedleLine& nl) { nl_ = nl; }
  const NeedleLine& needle() const { return nl_; }
  // Couples the path prefix whose current axial position is within `reach` (none when
  // !entered); a newly coupled node is tied at its current gap, released ones let go.
  void couple(bool entered, double reach, const Eigen::VectorXd& pu);
  // Node i lies on a channel `lateral` (along lateral j) off the reference axis (realtime3d's
  // path that follows the tip): once coupled it holds the needle there, moved with the tissue,
  // instead of tying at its gap.
  void setChannel(int i, int j, double lateral) { channel_[static_cast<std::size_t>(i * lat_ + j)] = lateral; }
  void measure(double s_tip, double s_exit, const Eigen::VectorXd& pu);
  int solve(const TissueDynamics& t, const AxialMotion& mo, double dt);  // active-set iterations

  // Elastic deflection of the needle along lateral j at arc length sigma from the base.
  double deflection(int j, double sigma) const;
  double slope(int j, double sigma) const;  // its derivative at the tip's arc length L
  double rigidLateral(int j, double p) const { return nl_.dB[j] + (p - nl_.sB) * nl_.tanphi[j]; }
  double lateralAt(int j, double p) const { return rigidLateral(j, p) + deflection(j, (p - nl_.sB) / nl_.cosphi); }
  int coupled() const { return k_; }
  int comps() const { return comps_; }
  const Eigen::VectorXd& loads() const { return f_; }  // path loads of the last solve
  // Node i's axial load from the shaft alone (friction): its path load less the known tip loads
  // (press, cutting) put on it, which the tip carries.
  double shaftAxialLoad(int i) const { return f_[comps_ * i] - fK_[comps_ * i]; }
  double position(int i) const { return pos_[static_cast<std::size_t>(i)]; }
  double contactLength(int i) const { return ell_[static_cast<std::size_t>(i)]; }
  FrictionStatus status(int i) const { return status_[static_cast<std::size_t>(i)]; }
  double tieLoad(int j, int i) const { return lambda_[static_cast<std::size_t>(i * lat_ + j)]; }
  const ShaftSettings& settings() const { return cfg_; }

 private:
  void addKnownLoads(const TissueDynamics& t);
  int assemble(const TissueDynamics& t, const AxialMotion& mo, double dt);
  void assembleMatrix(const Eigen::MatrixXd& S, int m);
  bool updateStatus(const TissueDynamics& t, const AxialMotion& mo, bool monotone);
  bool axialUnknown(int i) const;
  bool solveSmall(int m);
  ShaftSettings cfg_;
  int lat_ = 1, comps_ = 2, P_ = 0, k_ = 0;
  NeedleLine nl_;
  std::vector<FrictionStatus> status_;
  std::vector<double> offset_, channel_, sigma_, ell_, pos_, lambda_, axial_prev_;
  std::vector<int> idx_, order_;
  Eigen::VectorXd fK_, f_, y_, rhs_, x_, un_;
  Eigen::MatrixXd H_;
};

}  // namespace needlesim::realtime
