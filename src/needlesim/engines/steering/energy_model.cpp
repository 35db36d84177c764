#include "needlesim/engines/steering/energy_model.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include <Eigen/Dense>

#include "needlesim/materials/elastic_moduli.hpp"
#include "needlesim/needle/beam_element.hpp"
#include "needlesim/needle/section.hpp"

namespace needlesim::steering {

// Sub-step 1 push u that makes d Lambda_1 / d u = 0, capped at max_step; a roller
// along the axis (tau = 0) bends nothing, so the push is the cap [choice 4].
static double pushDistance(double P_eff, double k_eff, double tau, double max_step, bool& capped) {
  if (std::abs(tau) < 1e-12) {
    capped = true;
    return max_step;
  }
  const double u = P_eff / (k_eff * tau * tau);
  if (u > max_step) {
    capped = true;
    return max_step;
  }
  return u;
}
namespace {

using Vec4 = Eigen::Vector4d;
using Mat4 = Eigen::Matrix4d;

// Two Hermite pieces on [0, l/2] and [l/2, l] (eq 45) clamped at x = 0 (eqs 47-48):
// free coefficients c = (v(l/2), v'(l/2), v(l), v'(l)).
void assemble(double EI, double KT, double l, Mat4& Kb, Mat4& Kf) {
  const double h = l / 2;
  const Mat4 kb = needle::bendingStiffness(EI, h), kf = needle::foundationStiffness(KT, h);
  Kb.setZero();
  Kf.setZero();
  // element 0: dofs (fixed, fixed, 0, 1); element 1: (0, 1, 2, 3)
  Kb.topLeftCorner<2, 2>() += kb.bottomRightCorner<2, 2>();
  Kf.topLeftCorner<2, 2>() += kf.bottomRightCorner<2, 2>();
  Kb += kb;
  Kf += kf;
}

// Value and slope of the previous deflection (length l_old, coefficients c) at x;
// beyond the old tip it continues straight along the tip tangent [choice 2].
inline void evalPrev(const Vec4& c, double l_old, double x, double& v, double& dv) {
  if (l_old <= 0) {
    v = dv = 0;
    return;
  }
  if (x >= l_old) {
    v = c(2) + c(3) * (x - l_old);
    dv = c(3);
    return;
  }
  const double h = l_old / 2;
  Vec4 q;
  double xi;
  if (x <= h) {
    q << 0, 0, c(0), c(1);
    xi = x / h;
  } else {
    q = c;
    xi = (x - h) / h;
  }
  v = needle::hermiteN(xi, h).dot(q);
  dv = needle::hermiteDN(xi, h).dot(q);
}

// [choice 9] PathWindow: the Ritz trial space is `window_elements` Hermite pieces over a
// window of `window` foundation lengths behind the tip, in a frame attached to the cut
// path (v_{i-1} of eqs 35, 40, 42 = the channel, so the increment deflection is measured
// from it) and clamped to it at the window base (eqs 47-48 moved to the window base): the
// tissue holds the needle behind the window. Within the window the channel is straight in
// its own frame and the roller sits at beta from the tip tangent (eq 47, beta + phi with
// phi = the tip angle of eq 29 measured in that frame = 0). Near the entry the window
// reaches back into the support sheath (seed 002 section 2.4.2), taken as a straight
// continuation of the channel with the same support. The window problem is then the same
// in every increment: it is assembled and factored once, and each increment is linear in
// its advance. The tissue keeps the sub-step-2 tip position and tip rotation (the new
// channel node, as in the beam-on-foundation engine); the tip then advances straight.
EnergyResult runWindow(const EnergyParams& p, double EI, double EA, double A, double chi,
                       std::vector<Eigen::Vector3d>* path, double record_every, std::vector<EnergyIncrement>* incs) {
  const int ne = p.window_elements, nd = 2 * ne;
  const double lambda = std::sqrt(std::sqrt(p.K_T / (4 * EI)));
  const double Lw = p.window / lambda, h = Lw / ne;
  Eigen::MatrixXd Kb = Eigen::MatrixXd::Zero(nd, nd), Kf = Kb;
  const Mat4 kb = needle::bendingStiffness(EI, h), kf = needle::foundationStiffness(p.K_T, h);
  for (int e = 0; e < ne; ++e) {  // element e: dofs (2e-2, 2e-1, 2e, 2e+1); base clamped
    const int d[4] = {2 * e - 2, 2 * e - 1, 2 * e, 2 * e + 1};
    for (int i = 0; i < 4; ++i)
      for (int j = 0; j < 4; ++j)
        if (d[i] >= 0 && d[j] >= 0) {
          Kb(d[i], d[j]) += kb(i, j);  // eq 35, increment term
          Kf(d[i], d[j]) += kf(i, j);  // eq 40
        }
  }
  const Eigen::LDLT<Eigen::MatrixXd> ldlt(Kb + Kf);
  Eigen::VectorXd e = Eigen::VectorXd::Zero(nd);
  e(nd - 2) = 1.0;  // tip deflection dof
  const Eigen::VectorXd g = ldlt.solve(e);  // sub-step 1 shape per unit tip reaction
  const double k_eff = 1.0 / g(nd - 2);
  // sub-step 2 per unit V: K D = Kf D1 - Q e with D1 = V g, Q = V (phi = 0 in the frame)
  // [choices 1-2]
  const Eigen::VectorXd s2 = ldlt.solve(Kf * g - e);
  const double s2_UB = 0.5 * s2.dot(Kb * s2), s2_UT = 0.5 * s2.dot(Kf * s2);

  const double beta0 = p.beta_ratio * p.alpha;
  const double P_eff = (1.0 - p.friction_fraction) * p.P_input;  // Fig 23 [choice 7]
  const double tear = p.tear_length >= 0 ? p.tear_length : p.diameter / 2;
  EnergyResult r;
  struct Node {
    double s, x, y, th;
  };
  std::vector<Node> nodes;  // channel nodes (arc length, position, tangent angle)
  double l = p.initial_length, X = l, Y = 0.0, th = 0.0;
  nodes.push_back({0.0, 0.0, 0.0, 0.0});
  nodes.push_back({l, X, Y, th});
  if (path) path->push_back(Eigen::Vector3d(X, Y, 0));
  double next_record = l + record_every;
  size_t next_flip = 0;
  double sign = 1.0;
  while (l < p.insertion && r.increments < p.max_increments) {
    while (next_flip < p.flip_depths.size() && p.flip_depths[next_flip] <= l) {
      sign = -sign;
      ++next_flip;
    }
    const double tau = std::tan(sign * beta0);  // eq 47 in the path frame
    const double u2 = pushDistance(P_eff, k_eff, tau, p.max_step, r.capped);
    const double V = k_eff * tau * u2;  // eq 28 [choice 3]
    const double H = -V * tau;          // eq 27
    const double u0 = u2 - H * l / EA;  // base advance u(0)
    // [choice 10] only the share chi of the advance cuts sideways along the roller; the
    // rest is straight rupture advance, so the sideways cut (and everything sub-step 2
    // builds on it) is chi times the roller's
    const double Vc = chi * V;
    const double wt = Vc * s2(nd - 2), rt = Vc * s2(nd - 1);  // sub-step 2 tip deflection, rotation
    r.W_Q += -Vc * wt;                                         // eq 42
    r.W_P += H * H * l / EA;                                   // eq 43, u(l) - u(0) = -H l / EA
    r.U_B += Vc * Vc * s2_UB;                                  // eq 35, increment part
    r.U_T += Vc * Vc * s2_UT;                                  // eq 40
    r.W_input += p.P_input * u0;                               // eq 41 [choice 1]
    r.W_friction += p.friction_fraction * p.P_input * u0;      // Fig 23 [choice 7]
    r.W_R += tear * p.fracture_energy * u0;                    // eq 44 [choices 5, 10]
    // the tissue keeps the tip where sub-step 2 leaves it: new channel node
    X += -std::sin(th) * wt;
    Y += std::cos(th) * wt;
    th += rt;
    nodes.back() = {l, X, Y, th};
    ++r.increments;
    if (incs) {
      // display shape: the channel sampled at l/2 and l (small-slope entry frame)
      const double sh = 0.5 * l;
      const auto it = std::lower_bound(nodes.begin(), nodes.end(), sh, [](const Node& n, double v) { return n.s < v; });
      const Node& nh = it == nodes.end() ? nodes.back() : *it;
      const Vec4 c(nh.y, std::tan(nh.th), Y, std::tan(th));
      // released loads (sub-step 2): the transverse share chi of the roller's [choice 10]
      incs->push_back({l, X, Y, th, H * std::cos(th) - Vc * std::sin(th), H * std::sin(th) + Vc * std::cos(th), H, V, c});
    }
    const double l_old = l;
    if (path && (l + u0 >= next_record || l + u0 >= p.insertion)) {
      path->push_back(Eigen::Vector3d(X, Y, 0));
      next_record = l_old + record_every;
    }
    if (l_old + u0 >= p.insertion) break;  // last node recorded at the end of the insertion
    // advance straight along the new tip tangent (choice 2: beyond the tip v_{i-1} is straight)
    l += u0;
    X += std::cos(th) * u0;
    Y += std::sin(th) * u0;
    nodes.push_back({l, X, Y, th});
  }
  if (p.medium_volume > 0 && p.E_T > 0)  // eq 39 (reporting only)
    r.U_C = materials::bulkModulus(p.E_T, p.nu_T) * (A * l) * (A * l) / p.medium_volume;  // K = E_T / (3 (1 - 2 nu_T))
  r.final_deflection = Y;
  r.final_length = l;
  return r;
}

}  // namespace

double energyDeflection(const Eigen::Vector4d& c, double l, double x) {
  double v, dv;
  evalPrev(c, l, x, v, dv);
  return v;
}

namespace {
void checkParams(const EnergyParams& p) {
  if (!(p.diameter > 0 && p.E > 0 && p.K_T > 0 && p.P_input > 0))
    throw std::invalid_argument("energy model needs diameter, E, K_T and P_input > 0");
  if (!(p.alpha > 0 && p.alpha < std::numbers::pi / 2) || p.beta_ratio < 0 || p.beta_ratio > 1)
    throw std::invalid_argument("energy model needs 0 < alpha < 90 deg and 0 <= beta/alpha <= 1");
  if (!(p.fracture_energy >= 0))
    throw std::invalid_argument("energy model needs fracture_energy >= 0");
  if (!(p.friction_fraction >= 0 && p.friction_fraction < 1))
    throw std::invalid_argument("friction fraction must lie in [0, 1)");
  if (!(p.initial_length > 0 && p.max_step > 0 && p.insertion > p.initial_length))
    throw std::invalid_argument("energy model needs 0 < initial_length < insertion, max_step > 0");

  if (p.frame == EnergyFrame::PathWindow && !(p.window > 0 && p.window_elements >= 1))
    throw std::invalid_argument("energy model path window needs window > 0 and window_elements >= 1");
}
}  // namespace

EnergyResult runEnergyModel(const EnergyParams& p, std::vector<Eigen::Vector3d>* path,
                            double record_every, std::vector<EnergyIncrement>* incs) {
  checkParams(p);

  const needle::Section sec{p.E, p.diameter, p.inner_diameter};
  const double EI = sec.EI(), EA = sec.EA(), A = sec.area();
  const double P_eff = (1.0 - p.friction_fraction) * p.P_input;  // Fig 23 [choice 7]
  const double tear = p.tear_length >= 0 ? p.tear_length : p.diameter / 2;
  // [choice 10] share of the tip's input work P_eff u left for the sideways cut once the
  // rupture work a G_f u (eq 44 per advance) is paid
  const double chi = std::max(0.0, 1.0 - tear * p.fracture_energy / P_eff);
  if (p.frame == EnergyFrame::PathWindow) {
    EnergyResult r = runWindow(p, EI, EA, A, chi, path, record_every, incs);
    r.cut_share = chi;
    return r;
  }
  const double beta0 = p.beta_ratio * p.alpha;

  EnergyResult r;
  Vec4 c = Vec4::Zero();  // previous deflection coefficients
  double l_old = 0.0;     // length the coefficients refer to (0 = straight)
  double l = p.initial_length;
  double next_record = 0.0;
  size_t next_flip = 0;
  double sign = 1.0;  // bevel orientation: +1 initial, -1 after an odd number of flips
  if (path) path->push_back(Eigen::Vector3d(l, 0, 0));
  next_record = l + record_every;
  Mat4 Kb, Kf;
  while (l < p.insertion && r.increments < p.max_increments) {
    while (next_flip < p.flip_depths.size() && p.flip_depths[next_flip] <= l) {
      sign = -sign;
      ++next_flip;
    }
    assemble(EI, p.K_T, l, Kb, Kf);
    const Mat4 K = Kb + Kf;
    // previous configuration projected on the current trial space [choice 2]
    Vec4 vp;
    evalPrev(c, l_old, l / 2, vp(0), vp(1));
    evalPrev(c, l_old, l, vp(2), vp(3));
    const double phi = std::atan(vp(3));  // eq 29
    const double tau = std::tan(sign * beta0 + phi);

    // Sub-step 1 (eqs 30, 47): minimise 1/2 D^T K D + EA/(2l)(u2-u0)^2 - P u0 with the
    // roller D_v(l) = u(l) tan(beta + phi). Static condensation on v(l): the shape is
    // K^-1 e_v(l) scaled, k_eff = 1 / (K^-1)_{v(l) v(l)}.
    const Eigen::LDLT<Mat4> ldlt(K);
    const Vec4 g = ldlt.solve(Vec4(0, 0, 1, 0));
    const double k_eff = 1.0 / g(2);
    const double u2 = pushDistance(P_eff, k_eff, tau, p.max_step, r.capped);
    const double dv_tip = tau * u2;
    const double V = k_eff * dv_tip;      // eq 28, variationally consistent nodal reaction [choice 3]
    const double H = -V * tau;            // eq 27: EA/l (u(l) - u(0)); = -P_eff when not capped
    const double u0 = u2 - H * l / EA;    // base advance u(0)
    // global reactions (rotate by phi) released onto the needle in sub-step 2 [choice 1]
    const double cp = std::cos(phi), sp = std::sin(phi);
    const double Pg = H * cp - V * sp, Qg = H * sp + V * cp;

    // Sub-step 2 (eqs 31, 48): the tissue has ruptured along the roller path, so the
    // foundation now holds configuration b (D1) [choice 2]; the reactions are released,
    // i.e. applied reversed (Q_i = -Qg) [choice 1]. Minimise
    // 1/2 D^T Kb D + 1/2 (D - D1)^T Kf (D - D1) - Q_i D_v(l) - P_i (u(l) - u(0)), u(0) = 0:
    // K D = Kf D1 - Qg e_v(l). The needle springs back towards straight; what the
    // tissue retains is the increment's deflection.
    const Vec4 D1 = g * (V * g(2) > 0 ? dv_tip / g(2) : 0.0);
    const Vec4 D2 = chi * ldlt.solve(Kf * D1 - Vec4(0, 0, Qg, 0));  // [choice 10]
    const double u2b = -Pg * l / EA;
    r.W_Q += -chi * Qg * D2(2);                        // eq 42, released share [choice 10]
    r.W_P += -Pg * u2b;                                // eq 43
    r.U_B += 0.5 * D2.dot(Kb * D2);                   // eq 35, increment part
    r.U_T += 0.5 * D2.dot(Kf * D2);                   // eq 40
    r.W_input += p.P_input * u0;                      // eq 41 [choice 1]
    r.W_friction += p.friction_fraction * p.P_input * u0;  // Fig 23 [choice 7]
    r.W_R += tear * p.fracture_energy * u0;           // eq 44 per increment [choices 5, 10]
    c = vp + D2;
    l_old = l;
    ++r.increments;
    if (incs) incs->push_back({l, l, c(2), phi, Pg, chi * Qg, H, V, c});
    l += u0;
    if (path && (l >= next_record || l >= p.insertion)) {
      path->push_back(Eigen::Vector3d(l_old, c(2), 0));
      next_record = l_old + record_every;
    }
  }
  if (p.medium_volume > 0 && p.E_T > 0)  // eq 39 at the final length (reporting only)
    r.U_C = materials::bulkModulus(p.E_T, p.nu_T) * (A * l_old) * (A * l_old) / p.medium_volume;  // K = E_T / (3 (1 - 2 nu_T))
  r.final_deflection = c(2);
  r.final_length = l_old;
  r.cut_share = chi;
  return r;
}

}  // namespace needlesim::steering
